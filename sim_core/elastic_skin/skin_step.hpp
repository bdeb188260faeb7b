// Elastic skin step job. Inputs: the bone global transforms of the skeleton
// pose (engine::Engine::model) and this step's muscle state (after
// muscle::muscle_step). Output: SkinState::position, the relaxed skin.
//
//   1. virtual anchors mapped forward (§5.1) -> SkinState::anchor, ::normal
//   2. start from the anchors (or the last skin when params.warm_start)
//   3. params.iterations times (or until the largest move < solver.tolerance),
//      in this order:
//        relaxation round (§5.2, eqs. 1-2)
//        collision spheres under the anchors (§5.2)
//        reaction constraints with the fat layer (LEMAN §3, §5.6);
//        the last iteration removes all remaining penetration
//        -> max_relax[i]: the largest net move of a vertex in the round
//   4. count fat points still inside a primitive (stats.inside_after)
// Worst-case work: iterations * (edges + bands + vertices * (1 + primitives
// * newton_steps)); no allocation.
#pragma once

#include <span>

#include "sim_core/fixed/mat34.hpp"
#include "sim_core/muscle/muscle_model.hpp"
#include "sim_core/muscle/muscle_state.hpp"
#include "skin_dynamic.hpp"
#include "skin_state.hpp"

namespace sinew::elastic_skin {

// Static mode (SkinSolverParams::mode, the default): the relaxation above,
// stopped early once an iteration's largest move is below solver.tolerance
// (stats.converged, stats.iterations, stats.residual). Dynamic mode: see
// skin_dynamic.hpp; it needs the tick (the overload without one refuses it).
//
// Rejects (changing nothing) a bone span shorter than the model's joints, a
// muscle state not built for `muscles`, a state not built for `model`, or a
// model failing skin_check_indices.
LayerStatus skin_step(const SkinModel& model, const muscle::MuscleModel& muscles, const muscle::MuscleState& mstate,
                      std::span<const fx::Mat34> bones, SkinState* state);
LayerStatus skin_step(const SkinModel& model, const muscle::MuscleModel& muscles, const muscle::MuscleState& mstate,
                      std::span<const fx::Mat34> bones, const SkinTick& tick, SkinState* state);

}  // namespace sinew::elastic_skin
