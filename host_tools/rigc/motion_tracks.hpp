// Motion files as rig DOF tracks (<joint>.<DOF index>, degrees or model
// units): a BVH take mapped through the spec's [motion.bvh_joints] table
// (host_tools/motion/bvh_drive.hpp), or CSV joint tracks
// (host_tools/motion/csv_tracks.hpp) whose columns must all name rig inputs.
#pragma once

#include <string>
#include <vector>

#include "host_tools/motion/bvh_drive.hpp"
#include "host_tools/motion/csv_tracks.hpp"
#include "rig_spec.hpp"

namespace sinew::rigc {

// True when the path ends in .bvh (any case); otherwise it is read as CSV.
bool is_bvh_path(const std::string& path);

bool load_motion_tracks(const std::string& path, const RigSpec& spec,
                        const std::vector<motion::BvhJointName>& bvh_joints, motion::JointTracks* out,
                        std::string* error);

}  // namespace sinew::rigc
