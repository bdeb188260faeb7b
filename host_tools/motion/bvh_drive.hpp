// A BVH take as rig DOF tracks: each rig joint reads the local rotation (and
// position channels) of one BVH joint, found by the rig joint's own name or
// through a rename table (a rig spec's [motion.bvh_joints]), and projects it
// onto its DOF axes the way the runtime measures DOFs from a pose
// (pipeline_step_locals): a rotational DOF is the twist of the joint's
// rotation about the DOF axis, a translational DOF the offset from the rest
// position along it.
//
// The BVH joint's frame is taken as the rig joint's rest frame: a BVH joint at
// all-zero channels is the rig joint at rest, and BVH axes are the axes the
// rig's DOF axes are written in.
#pragma once

#include <string>
#include <vector>

#include "host_tools/motion/bvh.hpp"
#include "host_tools/motion/bvh_pose.hpp"
#include "host_tools/motion/csv_tracks.hpp"

namespace sinew::motion {

// One rig joint as the mapping needs it.
struct RigJointDofs {
  std::string name;
  bool rotation = true;    // rotational DOFs (degrees) or translational (model units)
  std::vector<Vec3> axes;  // unit DOF axes in the joint's rest frame, 0..3
};

// One entry of the rename table: rig joint <- BVH joint.
struct BvhJointName {
  std::string rig_joint;
  std::string bvh_joint;
  std::string where;  // "<spec>:<line>: [motion.bvh_joints] <key>", for errors
};

// For every rig joint, the BVH joint it reads (-1: none, the joint stays at
// rest). A table entry wins; otherwise a BVH joint of the same name. Fails,
// naming it, when a table entry names a rig joint the rig lacks or a BVH
// joint the file lacks, or when no rig joint finds a BVH joint at all.
bool resolve_bvh_joints(const Bvh& bvh, const std::vector<RigJointDofs>& rig, const std::vector<BvhJointName>& table,
                        std::vector<int>* bvh_joint_of_rig, std::string* error);

// Twist angle (degrees, in (-180, 180]) of a unit quaternion about a unit
// axis: 2 atan2(v . axis, w), as the runtime's measure_dofs.
double twist_degrees(const Quaternion& q, const Vec3& axis);

// The take as tracks named <rig joint>.<DOF index>, one per DOF of every rig
// joint (unmapped joints' tracks hold 0, the rest pose), sampled at every BVH
// frame (time = frame x Frame Time).
bool bvh_to_joint_tracks(const Bvh& bvh, const std::vector<RigJointDofs>& rig, const std::vector<BvhJointName>& table,
                         JointTracks* out, std::string* error);

}  // namespace sinew::motion
