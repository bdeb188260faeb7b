// Reaction constraints (LEMAN §3, §5.4, §6.11) with the fat layer (§5.6):
// each skin vertex's fat point p = v - fat * n (n: the anchor normal) is
// inside-tested against every active primitive; a point inside is moved out
// along the primitive's gradient (Newton steps on F), the same displacement
// is applied to the skin vertex. Only the normal component changes, so the
// skin stays free to slide tangentially. `gain` < 1 removes that fraction
// of the penetration (first-order critically damped approach, no overshoot).
#pragma once

#include "sim_core/muscle/muscle_state.hpp"
#include "skin_state.hpp"

namespace sinew::elastic_skin {

// Returns the number of vertices moved.
uint32_t apply_reaction_constraints(const SkinModel& model, const muscle::MuscleState& muscles, fx::Unit gain,
                                    SkinState* s);

// Fat points still inside an active primitive by more than `tolerance`
// (Q2.30 on the inside/outside function: F < 1 - tolerance).
uint32_t count_inside(const SkinModel& model, const muscle::MuscleState& muscles, fx::Unit tolerance,
                      const SkinState& s);

}  // namespace sinew::elastic_skin
