// The joint's frame in the commanded pose and the particles' skinned rest
// ("ideal") positions: each particle rigidly follows its bone's model
// transform (sph-elastic-joints-tresca §4.1: the ideal distance the
// tension restores).
#pragma once

#include "sph_state.hpp"

namespace sinew::sph {

struct JointFrame {
  const fx::Mat34* proximal;
  const fx::Mat34* distal;
  fx::Vec3 centre;  // Len: the distal joint's origin
  fx::Vec3 axis;    // Q2.30 unit flexion axis, model space
};

// False if the transforms span is too short for the model's joints.
bool joint_frame(const SphModel& m, std::span<const fx::Mat34> transforms, JointFrame* out);

// ideal[i] = M_bone(i) * rest_local[i].
void compute_ideal(SphState* st, const JointFrame& f);

}  // namespace sinew::sph
