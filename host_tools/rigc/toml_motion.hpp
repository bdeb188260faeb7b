// The [motion] table of a TOML rig spec: how motion files drive the rig.
//
//   [motion.bvh_joints]        # rig joint = BVH joint, for names that differ
//   shoulder = "RightArm"
//   elbow = "RightForeArm"
//
// Rig joints not listed read the BVH joint of their own name, if any.
// Unknown keys, values that are not strings and rig joints the rig lacks are
// refused with the file, the line and the key.
#pragma once

#include <toml++/toml.h>

#include <string>
#include <vector>

#include "host_tools/motion/bvh_drive.hpp"
#include "rig_spec.hpp"

namespace sinew::rigc {

bool read_toml_motion(const std::string& path, const toml::table& t, const RigSpec& spec,
                      std::vector<motion::BvhJointName>* out, std::string* error);

// The same from the file (parsed again).
bool load_toml_motion(const std::string& path, const RigSpec& spec, std::vector<motion::BvhJointName>* out,
                      std::string* error);

// The rig's joints as the BVH mapping sees them (names, DOF kinds and axes).
std::vector<motion::RigJointDofs> rig_joint_dofs(const RigSpec& spec);

}  // namespace sinew::rigc
