// The bar-net step job (barnet-driven-skinning): bone global transforms and
// joint angles in; node positions and wrapped fine-skin positions out.
//   1. control mesh skinning: every node's smooth-skinned position s; fixed
//      nodes keep it (x_f = s_f);
//   2. loads: each LoadRecord adds t(angle or external input) * force,
//      carried by its bone; with ForceDensityInputs, D is re-assembled
//      from the scaled q and re-factorised (fixed work per step);
//   3. eq. (4): D x = p - D_f x_f for x, y and z independently, with the
//      factor computed at init and p = D s + D_f s_f + loads (the load
//      holding the net at the skinned shape, plus the bound loads); with
//      x_f = s_f the holding load cancels exactly, so the step solves
//      D (x - s) = loads and returns x = s + D^-1 loads;
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
