// A force-density bar-net (barnet-driven-skinning, appendix): nodes fixed or
// free, bars with force densities q, loads on free nodes bound to joint
// angles, the coarse control mesh the net is coupled to, and the wrap binding
// of the fine skin to that mesh. Plain records in spans the caller (or the
// offline builder) owns; the runtime never copies or allocates them.
//
// Units and Q formats:
//   positions, offsets         Len   Q12.20 rig units (same unit as the rig)
//   force density q            Q16.16, q in [kMinForceDensity, kMaxForceDensity]
//   forces (loads)             Force Q8.24 in units of (1 force density) x (1 rig unit)
//   weights, barycentrics      Unit  Q2.30, summing to 2^30
//   angles                     signed binary angles (int32 view, 2^32 = a turn)
//   external input values      Q16.16 in the input's unit (pipeline ExternalInputRecord)
//   force-density scales       Q16.16, clamped to [kMinForceDensityScale, kMaxForceDensityScale]
#pragma once

#include <cstdint>
#include <span>

#include "sim_core/fixed/mat34.hpp"
#include "sim_core/layer/layer_status.hpp"

namespace sinew::barnet {

using ForceDensity = int32_t;  // Q16.16
using Force = int32_t;         // Q8.24
inline constexpr int kForceDensityFracBits = 16;
inline constexpr int kForceFracBits = 24;
inline constexpr ForceDensity kForceDensityOne = int32_t{1} << kForceDensityFracBits;

// Limits: they bound the work of a step and keep every intermediate inside
// int64 (see ldlt_skyline.hpp for the derivation).
inline constexpr ForceDensity kMinForceDensity = int32_t{1} << 8;   // 2^-8
inline constexpr ForceDensity kMaxForceDensity = int32_t{1} << 24;  // 256
inline constexpr uint32_t kMaxNodes = 4096;
inline constexpr uint32_t kMaxFreeNodes = 1024;
inline constexpr uint32_t kMaxBars = 16384;
inline constexpr uint32_t kMaxBarsPerNode = 16;
inline constexpr uint32_t kMaxLoads = 1024;
inline constexpr uint32_t kMaxExternalInputs = 64;
inline constexpr uint32_t kMaxForceDensityInputs = 64;
// A force-density scale read from an input is clamped to [2^-8, 2^8] (Q16.16),
// and the scaled q to [kMinForceDensity, kMaxForceDensity]: the factor's
// bounds (ldlt_skyline.hpp) then hold for every value the input can take.
inline constexpr int32_t kMinForceDensityScale = int32_t{1} << 8;
inline constexpr int32_t kMaxForceDensityScale = int32_t{1} << 24;
inline constexpr uint32_t kMaxTriangles = 8192;
inline constexpr uint32_t kMaxWrapVertices = 1u << 20;
inline constexpr uint32_t kMaxNodeInfluences = 4;
inline constexpr uint32_t kMaxJoints = 1024;
// Profile (envelope) entries of the factor: bounds factorisation and solve work.
inline constexpr uint32_t kMaxProfile = 1u << 18;

enum class NodeKind : uint8_t { kFree = 0, kFixed = 1 };

// A node of the net, which is also a vertex of the control mesh. Its skinned
// position is s = sum_k weight[k] * S(joint[k]) * rest, S = global x inverse
// bind (the smooth skinning of the control mesh). Fixed nodes take x_f = s_f:
// the skeleton carries them. Free nodes take eq. (4)'s equilibrium
// x = D^-1 (p - D_f x_f), so the fixed nodes pull them and the net takes its
// form from its boundary. p is the node's rest load plus its loads. The rest
// load p0 = D x0 + D_f x0_f (x0: the bind-pose positions `rest`, D and D_f
// from the bars' compiled q) is the load under which the bind pose is the
// net's equilibrium; the paper is silent on it (its nets are form-found from
// loads alone, their geometry "independent of the geometry" of the mesh), and
// without it a free node on a convex patch would sink into the convex hull of
// its neighbours (with q > 0 an unloaded free node is a weighted mean of its
// neighbours). Derived at init, not stored in the section. The step turns
// p0 by the node's blended bones (sum_k weight[k] * S(joint[k]) p0,
// renormalised to |p0|), so a bent joint turns the tissue's push without
// weakening it. With q scaled by q_inputs, p0 stays the compiled one: a
// softer net bulges further under it.
struct NodeRecord {
  fx::Vec3 rest;                // Len, bind pose, model space
  uint8_t kind = 0;             // NodeKind
  uint8_t influence_count = 0;  // 1..kMaxNodeInfluences
  uint16_t joint[kMaxNodeInfluences] = {};
  uint16_t reserved = 0;                     // explicit, zeroed: a record's bytes go into rig blobs as they are
  fx::Unit weight[kMaxNodeInfluences] = {};  // >= 0, sum 2^30
};

// A bar between two distinct nodes, with its force density (force / length).
struct BarRecord {
  uint32_t a = 0, b = 0;
  ForceDensity q = 0;
};

// A load on a free node, bound to one input v: activation
// t = clamp((v - angle_lo) / (angle_hi - angle_lo), 0, 1) and the load is
// t * force, expressed in the bind pose's model frame and carried by the
// skinning matrix of `joint` (so it turns with that bone). Several loads on
// one node add up (superposition).
// `input` counts over the runtime's input array: below input_count it is a
// joint angle (lo, hi signed binary angles); from input_count on it is the
// external input input - input_count (a sensor force, say), and lo, hi are
// Q16.16 values in that input's unit, so the input's value scales the force
// linearly between them.
struct LoadRecord {
  uint32_t node = 0;
  uint16_t joint = 0;
  uint16_t input = 0;                  // joint angle, or input_count + external input index
  int32_t angle_lo = 0, angle_hi = 0;  // angles, or Q16.16 input values; lo != hi
  fx::Vec3 force;                      // Force, at full activation
};

// A run of bars whose force densities follow an external input: each step
// q' = clamp(q * clamp(v, 2^-8, 2^8), q_min, q_max), v the input's Q16.16
// value read as a dimensionless scale (rounded once); v <= 0 (an input never
// fed reads 0) reads as 1, the compiled q. Runs may overlap: their
// scales then multiply, in record order. A model with any of these records
// re-assembles and re-factorises D every step (a fixed cost, see
// BarnetState::refactor_products).
struct ForceDensityInput {
  uint32_t input = 0;  // external input index (0 .. external_count - 1)
  uint32_t first_bar = 0;
  uint32_t bar_count = 0;  // >= 1; first_bar + bar_count <= bars
  uint32_t reserved = 0;   // explicit, zeroed
};

// A triangle of the control mesh (node indices). Its normal is
// cross(b - a, c - a), normalised.
struct ControlTriangle {
  uint32_t node[3] = {};
};

// Wrap binding of one fine skin vertex (computed offline): the vertex is
// bary . (a, b, c) + offset * n of its control triangle, so it follows the
// control mesh.
struct WrapRecord {
  uint32_t vertex = 0;    // index of the fine skin vertex in the rig
  uint32_t triangle = 0;  // control triangle
  fx::Unit bary[3] = {};  // sum 2^30 (may be slightly outside [0, 1])
  fx::Len offset = 0;     // along the triangle's unit normal
};

struct BarnetModel {
  uint32_t joint_count = 0;                 // joints of the rig the net was built for
  uint32_t input_count = 0;                 // joint-angle inputs (the rig's inputs)
  uint32_t vertex_count = 0;                // fine skin vertices of that rig
  std::span<const fx::Mat34> inverse_bind;  // one per joint
  std::span<const NodeRecord> nodes;
  std::span<const BarRecord> bars;
  std::span<const LoadRecord> loads;
  std::span<const ControlTriangle> triangles;
  std::span<const WrapRecord> wrap;
  uint32_t external_count = 0;                       // external inputs the loads and q_inputs may read
  std::span<const ForceDensityInput> q_inputs = {};  // empty: D is factorised once, at init
};

// The layer status (sim_core/layer/layer_status.hpp); messages name the
// offending record and field.
using layer::LayerError;
using layer::LayerStatus;

}  // namespace sinew::barnet
