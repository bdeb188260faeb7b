#include "node_transforms.hpp"

#include <Eigen/Geometry>

namespace sinew::oracle::detail {
namespace {

Eigen::Matrix4d local_matrix(const NodePose& pose) {
  if (pose.has_matrix) return pose.matrix;
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = rotation_matrix(pose.rotation) * pose.scale.asDiagonal();
  m.topRightCorner<3, 1>() = pose.translation;
  return m;
}

}  // namespace

Eigen::Matrix3d rotation_matrix(const Eigen::Vector4d& q) {
  return Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()).toRotationMatrix();  // Eigen takes w first
}

bool default_node_poses(const tinygltf::Model& model, NodePoses* poses, std::string* error) {
  poses->assign(model.nodes.size(), NodePose{});
  for (size_t n = 0; n < model.nodes.size(); ++n) {
    const tinygltf::Node& node = model.nodes[n];
    NodePose& pose = (*poses)[n];
    const std::string name = "node " + std::to_string(n);
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16) return *error = name + ": matrix must have 16 numbers", false;
      pose.has_matrix = true;
      pose.matrix = Eigen::Map<const Eigen::Matrix4d>(node.matrix.data());  // column-major, like glTF
    }
    if (!node.translation.empty()) {
      if (node.translation.size() != 3) return *error = name + ": translation must have 3 numbers", false;
      pose.translation = Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]);
    }
    if (!node.scale.empty()) {
      if (node.scale.size() != 3) return *error = name + ": scale must have 3 numbers", false;
      pose.scale = Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]);
    }
    if (!node.rotation.empty()) {
      if (node.rotation.size() != 4) return *error = name + ": rotation must have 4 numbers", false;
      const Eigen::Vector4d q(node.rotation[0], node.rotation[1], node.rotation[2], node.rotation[3]);
      if (!(q.norm() > 0)) return *error = name + ": rotation is not a valid quaternion", false;
      pose.rotation = q.normalized();  // the spec requires unit length; tolerate rounding in the file
    }
  }
  return true;
}

bool world_transforms(const tinygltf::Model& model, const NodePoses& poses, Matrices* world, std::string* error) {
  const size_t count = model.nodes.size();
  std::vector<int> parent(count, -1);
  for (size_t n = 0; n < count; ++n) {
    for (int child : model.nodes[n].children) {
      if (child < 0 || static_cast<size_t>(child) >= count) {
        *error = "node " + std::to_string(n) + " has a child " + std::to_string(child) + " that does not exist";
        return false;
      }
      if (parent[static_cast<size_t>(child)] != -1) {
        *error = "node " + std::to_string(child) + " has more than one parent";
        return false;
      }
      parent[static_cast<size_t>(child)] = static_cast<int>(n);
    }
  }
  world->assign(count, Eigen::Matrix4d::Identity());
  std::vector<bool> done(count, false);
  std::vector<size_t> chain;
  for (size_t n = 0; n < count; ++n) {
    // Walk up to the first node already done (or a root), then compose back down.
    chain.clear();
    for (size_t at = n; !done[at];) {
      chain.push_back(at);
      if (chain.size() > count) {
        *error = "node " + std::to_string(n) + " is its own ancestor (cycle in node children)";
        return false;
      }
      if (parent[at] < 0) break;
      at = static_cast<size_t>(parent[at]);
    }
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const size_t at = *it;
      const Eigen::Matrix4d local = local_matrix(poses[at]);
      (*world)[at] = parent[at] < 0 ? local : Eigen::Matrix4d((*world)[static_cast<size_t>(parent[at])] * local);
      done[at] = true;
    }
  }
  return true;
}

}  // namespace sinew::oracle::detail
