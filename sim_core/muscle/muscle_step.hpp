// Muscle step job (anatomically-based-modeling §4.4): bone global transforms
// in, slice frames, slice ring vertices and placed primitives out.
//
// Input: `bones`, one model-space transform per rig joint (engine::Engine::
// model after engine_step). For each muscle the four attachments and the
// pivot are mapped to model space; if none moved since the last step the
// muscle is left as it is (the paper recomputes only when a joint between
// origin and insertion moves). Otherwise the 8 slice frames are laid on the
// path origin midpoint -> (pivot) -> insertion midpoint, X interpolated
// between the origin and insertion lines, and the inner slices (1..6) scaled
// by s = sqrt(rest_length / present_length) so their cross-section area
// grows as the muscle shortens (§4.4). The ratio is clamped to [1/4, 3.99],
// so s lies in [1/2, 1.998).
// Work per step: O(muscles * 8 * ring_vertices + primitives), no allocation.
#pragma once

#include <span>

#include "muscle_state.hpp"
#include "sim_core/fixed/mat34.hpp"

namespace sinew::muscle {

// Validates the step inputs (bone count, state built for this model), then
// updates `state`. On error nothing is changed.
LayerStatus muscle_step(const MuscleModel& model, std::span<const fx::Mat34> bones, MuscleState* state);

}  // namespace sinew::muscle
