#pragma once
// Node local transforms (matrix, or translation * rotation * scale) and their
// composition into world transforms through each node's parent chain.
#include <Eigen/Core>
#include <Eigen/StdVector>
#include <string>
#include <vector>

#include "gltf_model.hpp"

namespace sinew::oracle::detail {

struct NodePose {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector4d rotation = Eigen::Vector4d(0, 0, 0, 1);  // x, y, z, w (glTF order), unit
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  bool has_matrix = false;  // node.matrix given: it replaces TRS and cannot be animated
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
};

using Matrices = std::vector<Eigen::Matrix4d, Eigen::aligned_allocator<Eigen::Matrix4d>>;
using NodePoses = std::vector<NodePose, Eigen::aligned_allocator<NodePose>>;

// Every node's own (unanimated) transform, in model.nodes order.
bool default_node_poses(const tinygltf::Model& model, NodePoses* poses, std::string* error);

// Unit quaternion (x, y, z, w) -> 3x3 rotation.
Eigen::Matrix3d rotation_matrix(const Eigen::Vector4d& q);

// World transform of every node: parent world * local, from the roots down.
// Fails if a child index is invalid or the node graph is not a forest.
bool world_transforms(const tinygltf::Model& model, const NodePoses& poses, Matrices* world, std::string* error);

}  // namespace sinew::oracle::detail
