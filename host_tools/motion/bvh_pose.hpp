// Poses from parsed BVH data: each joint's local rotation and translation at a
// frame, and forward kinematics to global joint positions.
#pragma once

#include <cstddef>
#include <vector>

#include "host_tools/motion/bvh.hpp"

namespace sinew::motion {

struct Quaternion {
  double w = 1, x = 0, y = 0, z = 0;
};

// The joint's local rotation at `frame`: its rotation channels composed in the
// order the file lists them (CHANNELS Zrotation Xrotation Yrotation gives
// Rz * Rx * Ry, so a point is rotated about Y first), angles in degrees, as a
// unit quaternion. Identity for a joint without rotation channels.
// Throws std::out_of_range for a joint or frame index out of range.
Quaternion local_rotation(const Bvh& bvh, size_t joint, size_t frame);

// The joint's OFFSET plus its position channels at `frame`.
Vec3 local_translation(const Bvh& bvh, size_t joint, size_t frame);

// Global joint positions at `frame` (p = p_parent + R_parent * t_local).
std::vector<Vec3> global_positions(const Bvh& bvh, size_t frame);

// Global joint positions with every channel at zero: the sums of the OFFSETs.
std::vector<Vec3> rest_global_positions(const Bvh& bvh);

// Global End Site positions in the rest pose.
std::vector<Vec3> rest_end_site_positions(const Bvh& bvh);

}  // namespace sinew::motion
