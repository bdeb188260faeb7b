#pragma once
// glTF 2.0 animation sampling: LINEAR (slerp on the shorter arc for
// rotations), STEP and CUBICSPLINE, time clamped to each sampler's keyframes.
#include <string>

#include "node_transforms.hpp"

namespace sinew::oracle::detail {

// Overrides the translation / rotation / scale of every node targeted by
// animation `animation` with its value at `time`. Morph-weight channels and
// channels without a target node are ignored.
bool apply_animation(const tinygltf::Model& model, int animation, double time, NodePoses* poses, std::string* error);

// First and last keyframe time over all samplers of animation `animation`.
bool animation_range(const tinygltf::Model& model, int animation, double* start, double* end, std::string* error);

}  // namespace sinew::oracle::detail
