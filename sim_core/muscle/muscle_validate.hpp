// Validation of a muscle model against the rig it will run on. Run once
// after loading; the step then only re-checks the indices it dereferences.
#pragma once

#include "layer_status.hpp"
#include "muscle_model.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::muscle {

// Rejects (kBadModel, message naming muscle/primitive index and field):
//  - a joint count differing from the rig's, ring_vertices not a multiple of 4 in [4, 64];
//  - attachment or pivot bones that are not joints of the rig;
//  - a muscle whose origin is not proximal to its insertion: every origin
//    bone must be the insertion bone or one of its ancestors (§4.1);
//  - pivot_slice outside 1..6, rest_length <= 0, negative slice radii;
//  - primitives of unknown kind/attach, exponent not in {2, 4, 8},
//    non-positive extents, an aspect ratio above kMaxPrimitiveAspect,
//    a sphere with unequal extents, a muscle segment outside 0..6.
LayerStatus muscle_validate(const MuscleModel& model, const rig::Rig& rig);

}  // namespace sinew::muscle
