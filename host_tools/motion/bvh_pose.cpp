#include "bvh_pose.hpp"

#include <Eigen/Geometry>
#include <numbers>
#include <span>
#include <stdexcept>

#include "text_scan.hpp"

namespace sinew::motion {

namespace {

// An all-zero row stands for the rest pose.
double channel_value(std::span<const double> row, size_t index) { return row.empty() ? 0.0 : row[index]; }

const BvhJoint& joint_at(const Bvh& bvh, size_t joint) {
  if (joint >= bvh.joints.size())
    throw std::out_of_range(cat("BVH joint ", std::to_string(joint), " of ", std::to_string(bvh.joints.size())));
  return bvh.joints[joint];
}

Eigen::Quaterniond rotation_of(const BvhJoint& joint, std::span<const double> row) {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  for (size_t c = 0; c < joint.channels.size(); ++c) {
    const BvhChannel channel = joint.channels[c];
    if (!is_rotation(channel)) continue;
    const double radians = channel_value(row, joint.first_value + c) * (std::numbers::pi / 180.0);
    q = q * Eigen::Quaterniond(Eigen::AngleAxisd(radians, Eigen::Vector3d::Unit(channel_axis(channel))));
  }
  return q.normalized();
}

Eigen::Vector3d translation_of(const BvhJoint& joint, std::span<const double> row) {
  Eigen::Vector3d t(joint.offset[0], joint.offset[1], joint.offset[2]);
  for (size_t c = 0; c < joint.channels.size(); ++c) {
    const BvhChannel channel = joint.channels[c];
    if (!is_rotation(channel)) t[channel_axis(channel)] += channel_value(row, joint.first_value + c);
  }
  return t;
}

Vec3 to_vec3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

std::vector<Vec3> forward_kinematics(const Bvh& bvh, std::span<const double> row) {
  std::vector<Eigen::Quaterniond> rotations(bvh.joints.size());
  std::vector<Eigen::Vector3d> positions(bvh.joints.size());
  std::vector<Vec3> out(bvh.joints.size());
  for (size_t j = 0; j < bvh.joints.size(); ++j) {
    const BvhJoint& joint = bvh.joints[j];
    const Eigen::Quaterniond local = rotation_of(joint, row);
    const Eigen::Vector3d t = translation_of(joint, row);
    // Parents precede children (the parser guarantees it), so the parent is done.
    if (joint.parent < 0) {
      rotations[j] = local;
      positions[j] = t;
    } else {
      const auto parent = static_cast<size_t>(joint.parent);
      rotations[j] = rotations[parent] * local;
      positions[j] = positions[parent] + rotations[parent] * t;
    }
    out[j] = to_vec3(positions[j]);
  }
  return out;
}

}  // namespace

Quaternion local_rotation(const Bvh& bvh, size_t joint, size_t frame) {
  const Eigen::Quaterniond q = rotation_of(joint_at(bvh, joint), bvh.frame(frame));
  return {q.w(), q.x(), q.y(), q.z()};
}

Vec3 local_translation(const Bvh& bvh, size_t joint, size_t frame) {
  return to_vec3(translation_of(joint_at(bvh, joint), bvh.frame(frame)));
}

std::vector<Vec3> global_positions(const Bvh& bvh, size_t frame) { return forward_kinematics(bvh, bvh.frame(frame)); }

std::vector<Vec3> rest_global_positions(const Bvh& bvh) { return forward_kinematics(bvh, {}); }

std::vector<Vec3> rest_end_site_positions(const Bvh& bvh) {
  const std::vector<Vec3> joints = rest_global_positions(bvh);
  std::vector<Vec3> out;
  out.reserve(bvh.end_sites.size());
  for (const BvhEndSite& site : bvh.end_sites) {
    const Vec3& base = joints.at(static_cast<size_t>(site.parent));
    out.push_back({base[0] + site.offset[0], base[1] + site.offset[1], base[2] + site.offset[2]});
  }
  return out;
}

}  // namespace sinew::motion
