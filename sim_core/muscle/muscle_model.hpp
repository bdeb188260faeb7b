// Deformed-cylinder muscles (anatomically-based-modeling §4) and implicit
// muscle primitives (LEMAN §5.2): the immutable model a builder produces
// (host_tools/layers/anatomy) and the runtime reads. Plain records behind
// spans; nothing here allocates.
//
// Units: every position and length is a Len (Q12.20 rig units, the rig's
// own length exponent); directions are Q2.30 unit vectors.
#pragma once

#include <cstdint>
#include <span>

#include "sim_core/fixed/vec3.hpp"

namespace sinew::muscle {

// 8 elliptical slices per muscle (7 sections), §4.1.
inline constexpr uint32_t kSlices = 8;
// Ring vertices per slice: a multiple of 4 (the anchoring cell uses the
// vertices at 0, 1/4, 1/2 and 3/4 of a turn), 4..kMaxRingVertices.
inline constexpr uint32_t kMaxRingVertices = 64;
inline constexpr uint32_t kMaxMuscles = 256;
inline constexpr uint32_t kMaxPrimitives = 256;
// Largest ratio between a primitive's extents (keeps gradients in range).
inline constexpr int32_t kMaxPrimitiveAspect = 64;

// A point fixed on a bone: a joint index and a position in that joint's
// frame (the builder turns the paper's bone-size parameters into it).
struct BonePoint {
  uint32_t bone = 0;
  fx::Vec3 local{0, 0, 0};  // Len, joint frame
};

struct MuscleRecord {
  BonePoint origin[2];     // proximal attachments (origin bones must be ancestors of insertion bones)
  BonePoint insertion[2];  // distal attachments
  // Optional pivot frame origin (§4.3): the path runs origin -> pivot ->
  // insertion and slice pivot_slice (1..6) sits on the pivot.
  int32_t pivot_bone = -1;  // -1: no pivot
  uint32_t pivot_slice = 0;
  fx::Vec3 pivot_local{0, 0, 0};
  // Rest half-axes of each slice ellipse: X across the muscle (width), Y its
  // thickness; Len, >= 0. End slices (0 and 7) never scale.
  fx::Len half_width[kSlices] = {};
  fx::Len half_thickness[kSlices] = {};
  // Displacement of each slice centre along -Y (outward from the bone, §4.2),
  // at rest; scaled with the slice's thickness.
  fx::Len bulge[kSlices] = {};
  // Path length at the rest pose (origin midpoint, pivot, insertion
  // midpoint); > 0. Inner slices scale by sqrt(rest_length / present length).
  fx::Len rest_length = 0;
};

enum class PrimitiveKind : uint8_t {
  kSphere = 0,          // extent[0] is the radius (extent[1..2] must equal it)
  kCylinder = 1,        // elliptic cross-section extent[0..1] about Z, half height extent[2]
  kSuperellipsoid = 2,  // Barr's superquadric (PrimitiveExponents); |x/a|^p + |y/b|^p + |z/c|^p < 1 for
                        // one exponent p
};

enum class PrimitiveAttach : uint8_t {
  kBone = 0,    // frame = the bone's frame (rigid bones: the linear part is a rotation)
  kMuscle = 1,  // frame = the slice frame of a muscle segment; extents follow the muscle's volume scale
};

// An implicit primitive the skin may not enter (LEMAN §5.2, §6.11).
struct PrimitiveRecord {
  uint8_t kind = 0;          // PrimitiveKind
  uint8_t attach = 0;        // PrimitiveAttach
  uint8_t exponent = 2;      // 2, 4 or 8: one exponent p, exact integer kernel (sphere, cylinder: 2);
                             // 0: a general superquadric, its exponents in MuscleModel::exponents
  uint8_t active = 1;        // inactive primitives are carried but never push the skin
  uint32_t index = 0;        // bone (joint) index or muscle index
  uint32_t segment = 0;      // muscle attach: centre between slices segment and segment + 1 (0..6)
  fx::Vec3 centre{0, 0, 0};  // Len: bone-frame centre, or offset in the slice frame for muscles
  fx::Len extent[3] = {};    // rest half-extents along the frame's X, Y, Z, > 0
};

// Barr's global deformations of a primitive (LEMAN §5.2, [Barr 84]) about
// its frame's Z axis, c = extent[2] its (present) half height. Applied in
// this order to the undeformed shape: taper, then twist, then bend.
//   taper: x, y scale by r(z) = 1 + taper * z / c
//   twist: x, y rotate about Z by twist * z / c
//   bend:  the Z axis bends towards +X on a circle of radius R = c / beta
//          (beta = bend in radians), the angle at z being bend * z / c
// All zero is the undeformed primitive, bit for bit. Validated ranges:
//   |taper| <= 1/2; |twist| <= a quarter turn;
//   bend 0 or 1/1024 <= |bend| <= 1/4 turn, and R >= 4 max(a, b) at rest
//   (the bend's centre stays clear of the primitive).
struct PrimitiveDeformation {
  fx::Unit taper = 0;  // Q2.30, taper rate over the half height
  int32_t twist = 0;   // binary angle (2^32 = one turn, signed) at z = +c
  int32_t bend = 0;    // binary angle (signed) of the axis' tangent at z = +c
  uint32_t reserved = 0;
};
inline constexpr fx::Unit kMaxTaper = fx::kUnitOne / 2;
inline constexpr int32_t kMaxTwist = int32_t{1} << 30;
inline constexpr int32_t kMinBend = int32_t{1} << 22;
inline constexpr int32_t kMaxBend = int32_t{1} << 30;

// Barr's superquadric exponents of a superellipsoid (LEMAN §5.2, [Barr 81];
// p = 2 / epsilon), in normalised coordinates q = (x/a, y/b, z/c):
//   F = (|qx|^power_xy + |qy|^power_xy)^(power_z / power_xy) + |qz|^power_z,
// inside when F < 1. Both in [1, 16] (epsilon in [1/8, 2]: convex, from
// diamond-like through the ellipsoid to box-like); spheres and cylinders
// exactly 2. A pair of equal exponents 2, 4 or 8 is the record's integer
// exponent (the exact kernel); any other pair needs the record's exponent 0.
inline constexpr int32_t kPowerTwo = int32_t{2} << 16;
inline constexpr int32_t kMinPower = int32_t{1} << 16;
inline constexpr int32_t kMaxPower = int32_t{16} << 16;
struct PrimitiveExponents {
  int32_t power_xy = kPowerTwo;  // Q16.16
  int32_t power_z = kPowerTwo;   // Q16.16
};

// The record exponent a pair of exponents needs: 2, 4 or 8 for an equal
// pair of those (the exact kernel), else 0 (the general superquadric).
inline constexpr uint8_t record_exponent(PrimitiveExponents e) {
  const int32_t p = e.power_xy;
  const bool exact = p == e.power_z && (p == 2 << 16 || p == 4 << 16 || p == 8 << 16);
  return exact ? static_cast<uint8_t>(p >> 16) : uint8_t{0};
}

// A muscle's non-default shape (anatomically-based-modeling §4.2 end
// frames, §4.3 and Table 1 edits). All fields at their defaults is the
// default shape, bit for bit.
enum class EndAxes : uint8_t {
  kPath = 0,         // end-slice Z along the path (origin -> first piece, last piece -> insertion)
  kBoneNormals = 1,  // §4.2: origin Z = mean outward bone normal at the origins, insertion Z = mean
                     // inward normal at the insertions, each made perpendicular to its end's X
};
enum class PivotMode : uint8_t {
  kFixed = 0,     // the pivot is on whenever pivot_bone >= 0 (Table 1: "on"; pivot_bone -1 is "off")
  kVariable = 1,  // Table 1 "variable": the pivot is used only while it lies on the outer (-Y) side of
                  // the straight origin -> insertion path, i.e. while the joint bends the muscle round it
};

// Table 1's per-slice edits of the slice frame, applied to the default
// frame (X, Y, Z) each step: the centre moves by translate (inner slices
// only: §4.3 "any intermediate slice can be translated"), then the frame
// turns to axis[0..2] (the rotated X, Y, Z in default-frame coordinates,
// the columns of the rotation). End slices may turn about X only (§4.3).
struct SliceEdit {
  fx::Vec3 translate{0, 0, 0};  // Len, along the default X, Y, Z; inner slices only
  fx::Vec3 axis[3] = {{fx::kUnitOne, 0, 0}, {0, fx::kUnitOne, 0}, {0, 0, fx::kUnitOne}};  // Q2.30, orthonormal
};

struct MuscleShape {
  uint8_t end_axes = 0;    // EndAxes
  uint8_t pivot_mode = 0;  // PivotMode; kVariable needs a pivot
  uint8_t reserved[2] = {};
  uint32_t reserved2 = 0;
  // EndAxes::kBoneNormals: the outward unit normals of the bones' surfaces
  // at origin[0], origin[1], insertion[0], insertion[1], each in its
  // attachment bone's frame (Q2.30); the builder computes them (§4.2).
  fx::Vec3 end_normal[4] = {};
  SliceEdit slice[kSlices];
};

struct MuscleModel {
  uint32_t joint_count = 0;    // joints of the rig the model was built for
  uint32_t ring_vertices = 8;  // per slice, multiple of 4 in [4, kMaxRingVertices]
  std::span<const MuscleRecord> muscles;
  std::span<const PrimitiveRecord> primitives;
  // Empty (no primitive deformed) or one per primitive.
  std::span<const PrimitiveDeformation> deformations;
  // Empty (every muscle has the default shape) or one per muscle.
  std::span<const MuscleShape> shapes = {};
  // Empty (every primitive's exponent is its record's) or one per primitive.
  std::span<const PrimitiveExponents> exponents = {};
};

}  // namespace sinew::muscle
