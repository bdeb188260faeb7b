// Validation of a skin model against its rig and muscle model. Run once
// after loading; the step re-checks only the indices it dereferences.
#pragma once

#include "sim_core/muscle/muscle_model.hpp"
#include "sim_core/rig/rig.hpp"
#include "skin_state.hpp"

namespace sinew::elastic_skin {

// Rejects (kBadModel, message naming the record index and field):
//  - span sizes that differ from vertex_count, a joint count differing from the rig's;
//  - anchors of unknown kind, bones that are not joints, weights outside [0, 1];
//  - muscle anchors naming no muscle or a segment outside 0..6, or whose
//    (s, t, u) lies outside the documented bounds: "outside every component";
//  - edges with an endpoint out of range or twice the same vertex, negative
//    rest lengths, stiffnesses above kMaxStiffness (also anchors and bands);
//  - negative fat; rubber bands naming no vertex, muscle, slice or ring vertex;
//  - parameters out of range (iterations 1..256, push_back [0, 1],
//    compression_band (0, 1], reaction_gain (0, 1], newton_steps 1..8,
//    collision_radius >= 0).
// The muscle model is the skin's one dependency: its anchors and bands
// name muscles (the skin runs after the muscle layer, in the anatomy stage).
LayerStatus skin_validate(const SkinModel& model, const rig::Rig& rig, const muscle::MuscleModel& muscles);

// The index and parameter checks alone (no rig needed); the step runs these every time.
LayerStatus skin_check_indices(const SkinModel& model, const muscle::MuscleModel& muscles, uint32_t joints);

}  // namespace sinew::elastic_skin
