#pragma once
// Linear blend skinning of every skinned mesh node, per the glTF 2.0 spec:
// v' = sum_i w_i * world(joint_i) * inverseBind(joint_i) * v.
#include <string>
#include <vector>

#include "node_transforms.hpp"

namespace sinew::oracle::detail {

struct SkinnedVertices {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> normals;  // empty, or one per position ((0,0,0) where a primitive has no NORMAL)
  int renormalized_vertices = 0;         // weight sums further than kWeightSumTolerance from 1
};

// Far above float rounding of a handful of weights (~1e-7), below one step of
// 8-bit quantised weights (1/255), so only genuinely unnormalised sums count.
inline constexpr double kWeightSumTolerance = 1e-4;

// Skins every node that has both a mesh and a skin, in model.nodes order, with
// the given world transforms. The mesh node's own transform is ignored (spec).
bool skin_model(const tinygltf::Model& model, const Matrices& world, SkinnedVertices* out, std::string* error);

}  // namespace sinew::oracle::detail
