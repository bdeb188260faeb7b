// The bar-net step job (barnet-driven-skinning): bone global transforms and
// joint angles in; node positions and wrapped fine-skin positions out.
//   1. control mesh skinning: every node's smooth-skinned position s; fixed
//      nodes keep it (x_f = s_f, the skeleton carries them);
//   2. loads p: each free node's rest load (the load under which the bind
//      pose is the net's equilibrium, barnet_model.hpp), turned by the
//      node's bones, plus each LoadRecord's t(angle or external input) *
//      force, carried by its bone; with ForceDensityInputs, D is
//      re-assembled from the scaled q and re-factorised (fixed work per
//      step);
//   3. eq. (4): x = D^-1 (p - D_f x_f) for x, y and z independently, with
//      the factor computed at init (solved for x - s, barnet_step.cpp);
//   4. wrap: each bound fine vertex = bary . triangle + offset * normal.
#pragma once

#include <cstdint>
#include <span>

#include "barnet_state.hpp"

namespace sinew::barnet {

struct StepInputs {
  std::span<const fx::Mat34> bones;        // model-space joint transforms, >= joint_count
  std::span<const int32_t> joint_angles;   // signed binary angles, >= input_count
  std::span<const int32_t> external = {};  // external inputs, Q16.16 in their units, >= external_count
};

struct StepOutputs {
  std::span<fx::Len> node[3];  // >= node count each
  std::span<fx::Len> skin[3];  // >= wrap count each; entry w is vertex model.wrap[w].vertex
};

// Returns kBadInput (changing nothing) if a span is too short.
LayerStatus barnet_step(BarnetState* state, const StepInputs& in, const StepOutputs& out);

}  // namespace sinew::barnet
