// Runtime state of a bar-net, carved from caller memory at init: the LDL^T
// factor of D (computed here, in fixed point, once), the rest load of every
// free node (derived here from the bind pose, see barnet_model.hpp), the
// per-step load and solve vectors, the skinning matrices and the
// control-mesh normals. After
// init nothing allocates; a step's work is bounded by the model's counts.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "barnet_model.hpp"
#include "ldlt_skyline.hpp"

namespace sinew::barnet {

struct StepStats {
  uint64_t steps = 0;
  uint32_t saturated = 0;  // values clamped in the last step
  // Largest |solved - smoothly skinned| over the free nodes in the last step,
  // per component (Len): how far the net's equilibrium lies from the
  // smoothly skinned control mesh.
  fx::Len max_displacement = 0;
};

// A control triangle as the wrap reads it: its corner nodes' positions (Len)
// and its unit normal (Q2.30), side by side. The pad (always 0) lets a
// vector kernel load the normal as four words without reading past the
// frame (wrap_avx2.cpp).
struct TriangleFrame {
  fx::Vec3 corner[3];
  fx::Vec3 normal;
  int32_t pad = 0;
};

// A skinning matrix as the node-skinning kernel reads it
// (node_skinning_avx2.cpp): column c of the linear part in int64 lanes 0..2,
// the translation times 2^24 likewise, lane 3 zero. Laid out each step.
struct SkinColumns {
  int64_t column[3][4];
  int64_t translation[4];
};

struct BarnetState {
  const BarnetModel* model = nullptr;
  uint32_t free_count = 0;
  SkylineFactor factor;
  std::span<ForceDensity> q;            // per bar, the force density of this step (the model's, scaled by q_inputs)
  std::span<fx::Mat34> skin;            // per joint: global x inverse bind
  std::span<SkinColumns> skin_columns;  // per joint: `skin` as the vector kernel reads it
  std::span<int64_t> load[3];           // per free node, p of eq. (4) this step: Q.36 force (rest load + loads)
  std::span<fx::Len> skinned[3];        // per free node, smooth-skinned position
  std::span<fx::Vec3> rest_direction;   // per free node, the rest load's unit direction in the bind pose, Q2.30
  std::span<int64_t> rest_magnitude;    // per free node, |rest load|, Q.36 force (< 2^62)
  std::span<int64_t> work;              // 3 per free node: the solve vectors of x, y, z (node i at 3 i + c)
  std::span<TriangleFrame> triangle;    // per control triangle, this step's corners and unit normal
  // Every wrap record has |b0| + |b1| + |b2| <= 2^31 and |offset| <= 2^30
  // (barnet_init): the wrap's sums then fit int64 without saturating
  // (barnet_step.cpp).
  bool wrap_bounded = false;
  // The kernels of the solve and the wrap (vector_kernel.hpp): at init, the
  // fastest the CPU runs (tests set the specification's to compare).
  VectorKernel kernel = VectorKernel::kScalar;
  uint32_t profile = 0;  // entries of L
  // Work of one factorisation of D (64x64-bit products, barnet_refactor.hpp):
  // paid at init, and at every step when the model has q_inputs.
  uint64_t refactor_products = 0;
  StepStats stats;
};

// Bytes barnet_init needs (8-byte aligned), or 0 if the model is invalid.
size_t barnet_state_bytes(const BarnetModel& model);

// Validates the model (barnet_validate plus: at most kMaxBarsPerNode bars on
// a node, a path of bars from every free node to a fixed node, the profile
// limit, positive pivots), carves the arena, derives the rest loads and
// factorises D. The model's
// spans must outlive the state.
LayerStatus barnet_init(const BarnetModel& model, void* arena, size_t arena_bytes, BarnetState* out);

}  // namespace sinew::barnet
