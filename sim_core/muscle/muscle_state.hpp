// Runtime state of the muscle layer, carved from caller memory at init
// (muscle_state_bytes tells how much); the step writes only into it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "layer_status.hpp"
#include "muscle_model.hpp"

namespace sinew::muscle {

// A slice coordinate frame (§4.2): centre on the muscle axis, Z along the
// axis towards the insertions, X across (width), Y = Z x X (thickness; -Y
// points outward from the bone). Radii are the present ellipse half-axes.
struct SliceFrame {
  fx::Vec3 centre{0, 0, 0};                     // Len
  fx::Vec3 x{0, 0, 0}, y{0, 0, 0}, z{0, 0, 0};  // Q2.30 unit
  fx::Len radius_x = 0, radius_y = 0;
};

// A general superquadric's exponents (PrimitiveExponents) and the terms its
// sampler derives from them and the present extents, set once per step by
// superquadric_prepare (superquadric.hpp). Logarithms are base 2, Q30.
struct SuperquadricTerms {
  int32_t power_xy = kPowerTwo, power_z = kPowerTwo;  // Q16.16, [1, 16]
  int64_t ratio = int64_t{1} << 58;                   // e = p_z / p_xy, Q58 (its rounding is then far below
                                                      // the Q30 logarithms' even where |log2 S| reaches 500)
  int64_t inverse_power_z = int64_t{1} << 59;         // 1 / p_z, Q60
  int64_t log2_power_z = int64_t{1} << 30;            // log2 p_z
  int64_t log2_extent[3] = {};                        // log2 of each extent in Len LSBs
  int64_t log2_emax = 0;                              // log2 of the largest extent in Len LSBs
};

// A primitive placed for this step: world (model-space) centre, unit axes,
// present half-extents and its global deformation (muscle_model.hpp).
// `exponent` is the record's: 2, 4 or 8 take the exact integer kernel; a
// superellipsoid with 0 is a general superquadric (`superquadric`).
struct PrimitiveFrame {
  fx::Vec3 centre{0, 0, 0};
  fx::Vec3 axis[3] = {};
  fx::Len extent[3] = {};
  uint8_t kind = 0, exponent = 2, active = 0;
  PrimitiveDeformation deformation;
  SuperquadricTerms superquadric;
};

struct MuscleStats {
  uint64_t steps = 0;
  uint32_t recomputed = 0;  // muscles whose attachments moved in the last step
  uint32_t degenerate = 0;  // fallback axes used (coincident attachments), last step
};

struct MuscleState {
  uint32_t ring_vertices = 0;
  std::span<fx::Unit> ring_cos, ring_sin;  // Q2.30, per ring vertex j: angle j / ring turns
  std::span<SliceFrame> frames;            // [muscle * kSlices + slice]
  std::span<fx::Len> vertex[3];            // SoA, [(muscle * kSlices + slice) * ring + j]
  std::span<fx::Len> length;               // present path length per muscle
  std::span<fx::Unit> scale;               // sqrt(rest / present), Q2.30, per muscle
  std::span<fx::Vec3> last_points;         // 5 per muscle: attachments of the last recompute
  std::span<uint8_t> computed;             // per muscle: 1 once computed
  std::span<PrimitiveFrame> primitives;
  MuscleStats stats;
};

inline uint32_t muscle_vertex_index(uint32_t ring, uint32_t muscle, uint32_t slice, uint32_t j) {
  return (muscle * kSlices + slice) * ring + j;
}

size_t muscle_state_bytes(const MuscleModel& model);

// Carves `memory` (8-byte aligned, >= muscle_state_bytes) and fills the ring
// tables. Fails with kArena or kBadValue (ring_vertices out of range).
LayerStatus muscle_init(const MuscleModel& model, void* memory, size_t bytes, MuscleState* out);

}  // namespace sinew::muscle
