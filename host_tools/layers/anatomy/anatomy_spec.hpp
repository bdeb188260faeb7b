// Offline description of the anatomy layers (muscles, primitives, elastic
// skin), in double precision and model units (metres for the built-in
// rigs). build_anatomy() turns it into the fixed-point models of
// sim_core/muscle and sim_core/elastic_skin. docs/anatomy.md lists the
// intended TOML keys, one per field.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "host_tools/rigc/rig_spec.hpp"

namespace sinew::anatomy_build {

using rigc::Vec3d;

// The "bounding box" of a bone (anatomically-based-modeling §4.1): muscle
// attachments are given in units of it, so one muscle description fits
// bones of any size: a point (px, py, pz) is (px * length, py * radius,
// pz * radius) in the joint's frame.
// The bone runs along `axis` of its joint's frame (X for the built-in
// rigs; glTF skeletons often use Y) and `side` (perpendicular to it) is the
// point's second coordinate: (px, py, pz) is px * length * axis +
// py * radius * side + pz * radius * (axis x side).
struct BoneSize {
  double length = 0.1;
  double radius = 0.01;
  Vec3d axis{1, 0, 0};
  Vec3d side{0, 1, 0};
};

struct BoneAttachment {
  int bone = 0;          // joint index
  Vec3d param{0, 0, 0};  // bone-size units
};

// Table 1's per-slice frame edits (anatomically-based-modeling §4.3), from
// the default slice frame: the centre moves by `translate` (model units,
// along the default X, Y, Z; inner slices 1..6 only, |translate| at most
// the muscle's rest length), then the frame turns by `rotate` (degrees,
// about X first, then Y, then Z of the default frame: R = Rz Ry Rx; each in
// [-90, 90]; end slices 0 and 7 about X only).
struct SliceEditSpec {
  Vec3d translate{0, 0, 0};
  Vec3d rotate{0, 0, 0};
};

struct MuscleSpec {
  std::string name;
  BoneAttachment origin[2];     // the X axis of the first slice runs origin[0] -> origin[1]
  BoneAttachment insertion[2];  // ... of the last slice insertion[0] -> insertion[1]
  bool has_pivot = false;
  BoneAttachment pivot;
  int pivot_slice = 6;                     // 1..6
  std::array<double, 8> half_width{};      // rest ellipse half-axes across (X), model units
  std::array<double, 8> half_thickness{};  // ... and in thickness (Y)
  std::array<double, 8> bulge{};           // slice centre displacement outward (-Y)
  // §4.2: end-slice Z from the averaged outward (origin) / inward
  // (insertion) normals of the bones' surfaces at the attachments, instead
  // of the path direction. A bone's surface is its box's capsule: radius
  // `radius` around the segment 0..length along its axis.
  bool end_axes_from_bones = false;
  // Table 1 pivot "variable" (needs has_pivot): the pivot is used only
  // while it lies outward (-Y) of the straight path (muscle_model.hpp).
  bool pivot_variable = false;
  std::array<SliceEditSpec, 8> slice_edit{};
};

struct PrimitiveSpec {
  int kind = 2;    // muscle::PrimitiveKind: 0 sphere, 1 cylinder, 2 superellipsoid
  int attach = 1;  // muscle::PrimitiveAttach: 0 bone, 1 muscle
  // Barr's superquadric exponents (LEMAN §5.2, muscle_model.hpp
  // PrimitiveExponents): `exponent` across (x, y), `exponent_z` along z (0:
  // the same), each in [1, 16]; spheres and cylinders 2. Equal 2, 4 or 8
  // take the exact integer kernel, any other pair the general one.
  double exponent = 2;
  double exponent_z = 0;
  bool active = true;
  int index = 0;                   // bone or muscle
  int segment = 3;                 // muscle attach: between slices segment and segment + 1
  Vec3d centre{0, 0, 0};           // bone frame, or offset in the slice frame (model units)
  Vec3d extent{0.01, 0.01, 0.01};  // half-extents (model units)
  // Barr's deformations about the frame's Z (LEMAN §5.2, muscle_model.hpp):
  // taper rate in [-1/2, 1/2]; twist and bend in degrees at z = +c, |twist|
  // <= 90, bend 0 or 360/1024 <= |bend| <= 90.
  double taper = 0, twist = 0, bend = 0;
};

// LEMAN §5.5: a rubber band binds a skin point to the muscle layer where a
// ray from it, perpendicular to the skin (along the inward rest normal),
// meets the muscle's surface; the band's target is the muscle ring vertex
// nearest that hit. `vertex` names the skin point; -1 selects the skin
// vertex nearest the muscle point (slice, ring_vertex) at rest, whose ray
// is then traced the same way.
struct RubberBandSpec {
  int vertex = -1;  // skin vertex; -1: the one nearest the muscle point (slice, ring_vertex) at rest
  int muscle = 0, slice = 4, ring_vertex = 0;
  double stiffness = 0.5;
  std::string label;  // names the band in errors (a spec table's line); empty: "rubber band <index>"
};

// The skin solver (elastic_skin::SkinSolverParams) in model units, seconds
// and kg; the builder converts to rig units.
struct SkinSolverSpec {
  double tolerance = 0;   // static: stop relaxing once the largest move is below this; 0: every iteration
  double fat_global = 0;  // added to every vertex's fat (LEMAN §5.6)
  // LEMAN §5.6: offset the fat along the skin mesh's current normal,
  // re-estimated every pass, instead of along the anchor's normal.
  bool fat_surface_normal = false;
  bool dynamic = false;  // LEMAN §3 mass-spring skin instead of the static relaxation
  // Dynamic: target substep rate; 0: the lowest multiple of 1 kHz with
  // h omega_max <= 1 (the runtime's stability bound; omega_max the
  // Gershgorin bound of the stiffest mode).
  int substep_hz = 0;
  int max_substeps = 16;  // with substep_hz 0, raised so that a 100 Hz loop fits (at most 64)
  int constraint_passes = 3;
  // The tissue (docs/anatomy.md, "Physical defaults"): each value <= 0 (or
  // < 0 for the dampings) is derived. Model units are taken as metres.
  double vertex_mass = 0;         // kg per vertex; 0: surface_density x skin area / vertices
  double surface_density = 3.0;   // kg/m^2: skin and the tissue it carries (about 3 mm at 1000 kg/m^3)
  double frequency = 10;          // Hz: a vertex of mean anchor stiffness on its anchor spring
  double damping_ratio = 0.3;     // of that oscillator, from the anchor dashpot
  double stiffness_scale = 0;     // N per model unit for a model stiffness of 1; 0: m (2 pi f)^2 / mean k_a
  double anchor_damping = -1;     // N s per model unit; < 0: 2 zeta m 2 pi f
  double band_damping = -1;       // N s per model unit; < 0: the anchor's
  double gravity[3] = {0, 0, 0};  // model units / s^2
  double edge_damping = 0;        // N s per model unit, dashpot along each skin edge (SKIN v3), >= 0
  // Dynamic: LEMAN §6.11's relaxation (one implicit step per tick, solved by
  // Gauss-Seidel sweeps; SKIN v6) rather than explicit substeps.
  bool relaxation = true;
  int relaxation_iterations = 3;  // sweeps per step (§6.11: "two to four"), 1..8
  double bend = 0.1;              // model stiffness of the surface's bend term (x stiffness_scale), [0, 256]
  double pressure = 0;            // §5.3 internal air pressure, N/m^2 (model units as metres)
  double reaction_frequency = 0;  // Hz of the critically damped reaction; 0: 10 x frequency
};

struct SkinSpec {
  int iterations = 30;
  double anchor_coefficient = 0.1;  // C_a of eq. (2)
  double rest_length_ratio = 1.0;   // rest = ratio * extracted length (§5.2)
  double push_back = 0.1;
  double compression_band = 0.1;
  double collision_radius = 0.02;                     // model units; 0 disables
  double fat = 0.006;                                 // uniform fat thickness (model units)
  std::vector<std::pair<int, double>> fat_overrides;  // (vertex, thickness)
  double reaction_gain = 0.5;
  int newton_steps = 3;
  bool warm_start = false;
  // Anchoring (§5.1): a vertex farther than this from every component's
  // surface is rejected ("anchor outside every component").
  double max_anchor_distance = 0.06;
  std::vector<RubberBandSpec> bands;
  SkinSolverSpec solver;
};

struct AnatomySpec {
  std::vector<BoneSize> bones;  // one per joint
  std::vector<MuscleSpec> muscles;
  std::vector<PrimitiveSpec> primitives;
  int ring_vertices = 8;
  SkinSpec skin;
};

// The built-in arm's anatomy: a biceps (upper arm -> forearm, front, with a
// pivot in front of the elbow) and a triceps (upper arm -> olecranon, back,
// with a pivot behind the elbow),
// one superellipsoid primitive each, rubber bands at their bellies.
AnatomySpec arm_anatomy(const rigc::RigSpec& arm);

}  // namespace sinew::anatomy_build
