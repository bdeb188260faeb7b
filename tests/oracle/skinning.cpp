#include "skinning.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>

#include "accessor_reader.hpp"

namespace sinew::oracle::detail {
namespace {

struct Influence {
  size_t joint;   // index into skin.joints
  double weight;  // already divided by the vertex's weight sum
};

// Joint palette: world(joint) * inverseBind(joint) for every joint of the skin.
bool joint_matrices(const tinygltf::Model& model, int skin_index, const Matrices& world, Matrices* palette,
                    std::string* error) {
  const tinygltf::Skin& skin = model.skins[static_cast<size_t>(skin_index)];
  const std::string what = "skin " + std::to_string(skin_index);
  if (skin.joints.empty()) return *error = what + ": has no joints", false;
  AccessorData inverse_binds;
  if (skin.inverseBindMatrices >= 0) {
    if (!read_accessor(model, skin.inverseBindMatrices, TINYGLTF_TYPE_MAT4, what + " inverseBindMatrices",
                       &inverse_binds, error))
      return false;
    if (inverse_binds.count < skin.joints.size()) {
      *error = what + ": " + std::to_string(inverse_binds.count) + " inverse bind matrices for " +
               std::to_string(skin.joints.size()) + " joints";
      return false;
    }
  }
  palette->assign(skin.joints.size(), Eigen::Matrix4d::Identity());
  for (size_t j = 0; j < skin.joints.size(); ++j) {
    const int node = skin.joints[j];
    if (node < 0 || static_cast<size_t>(node) >= world.size()) {
      *error = what + ": joint " + std::to_string(j) + " names node " + std::to_string(node) + ", which does not exist";
      return false;
    }
    Eigen::Matrix4d inverse_bind = Eigen::Matrix4d::Identity();  // spec default when the accessor is absent
    if (skin.inverseBindMatrices >= 0)
      inverse_bind = Eigen::Map<const Eigen::Matrix4d>(&inverse_binds.values[16 * j]);  // column-major
    (*palette)[j] = world[static_cast<size_t>(node)] * inverse_bind;
  }
  return true;
}

// Every (joint, weight) of one primitive's vertices from all JOINTS_n / WEIGHTS_n sets.
bool read_influences(const tinygltf::Model& model, const tinygltf::Primitive& primitive, size_t vertex_count,
                     size_t joint_count, const std::string& what, std::vector<std::vector<Influence>>* influences,
                     int* renormalized, std::string* error) {
  influences->assign(vertex_count, {});
  int sets = 0;
  for (int set = 0;; ++set) {
    const std::string joints_name = std::string("JOINTS_").append(std::to_string(set));
    const std::string weights_name = std::string("WEIGHTS_").append(std::to_string(set));
    const auto joints_it = primitive.attributes.find(joints_name);
    const auto weights_it = primitive.attributes.find(weights_name);
    const bool has_joints = joints_it != primitive.attributes.end();
    if (has_joints != (weights_it != primitive.attributes.end())) {
      *error = what + ": " + joints_name + " and " + weights_name + " must come together";
      return false;
    }
    if (!has_joints) break;
    ++sets;
    AccessorData joints, weights;
    if (!read_accessor(model, joints_it->second, TINYGLTF_TYPE_VEC4, joints_name + " of " + what, &joints, error) ||
        !read_accessor(model, weights_it->second, TINYGLTF_TYPE_VEC4, weights_name + " of " + what, &weights, error))
      return false;
    if (joints.count != vertex_count || weights.count != vertex_count) {
      *error = what + ": " + joints_name + " or " + weights_name + " count differs from POSITION count " +
               std::to_string(vertex_count);
      return false;
    }
    for (size_t v = 0; v < vertex_count; ++v) {
      for (int c = 0; c < 4; ++c) {
        const double weight = weights.at(v, c);
        const double joint = joints.at(v, c);
        if (!(weight >= 0) || !std::isfinite(weight)) {
          *error = what + ": vertex " + std::to_string(v) + " has an invalid weight " + std::to_string(weight);
          return false;
        }
        if (weight == 0) continue;  // unused slot: its joint index does not matter
        if (joint < 0 || joint != std::floor(joint) || joint >= static_cast<double>(joint_count)) {
          *error = what + ": vertex " + std::to_string(v) + " uses joint index " + std::to_string(joint) +
                   ", out of range of the skin's " + std::to_string(joint_count) + " joints";
          return false;
        }
        (*influences)[v].push_back({static_cast<size_t>(joint), weight});
      }
    }
  }
  if (sets == 0) return *error = what + ": skinned primitive has no JOINTS_0/WEIGHTS_0", false;
  for (size_t v = 0; v < vertex_count; ++v) {
    double sum = 0;
    for (const Influence& influence : (*influences)[v]) sum += influence.weight;
    if (!(sum > 0)) return *error = what + ": vertex " + std::to_string(v) + " has all weights zero", false;
    if (std::fabs(sum - 1.0) > kWeightSumTolerance) ++*renormalized;
    for (Influence& influence : (*influences)[v]) influence.weight /= sum;  // harmless when sum is 1
  }
  return true;
}

// Normal transform: the inverse transpose of the linear part, computed as the
// cofactor matrix (columns a1 x a2, a2 x a0, a0 x a1) times the sign of the
// determinant, which equals it up to a positive scale and never divides.
Eigen::Vector3d transform_normal(const Eigen::Matrix3d& a, const Eigen::Vector3d& normal) {
  Eigen::Matrix3d cofactor;
  cofactor.col(0) = a.col(1).cross(a.col(2));
  cofactor.col(1) = a.col(2).cross(a.col(0));
  cofactor.col(2) = a.col(0).cross(a.col(1));
  Eigen::Vector3d n = cofactor * normal;
  if (a.determinant() < 0) n = -n;
  const double length = n.norm();
  return length > 0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::Zero();
}

bool skin_primitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive, const Matrices& palette,
                    const std::string& what, SkinnedVertices* out, bool* has_normals, std::string* error) {
  const auto position_it = primitive.attributes.find("POSITION");
  if (position_it == primitive.attributes.end()) return *error = what + ": has no POSITION", false;
  AccessorData positions, normals;
  if (!read_accessor(model, position_it->second, TINYGLTF_TYPE_VEC3, "POSITION of " + what, &positions, error))
    return false;
  const auto normal_it = primitive.attributes.find("NORMAL");
  *has_normals = normal_it != primitive.attributes.end();
  if (*has_normals) {
    if (!read_accessor(model, normal_it->second, TINYGLTF_TYPE_VEC3, "NORMAL of " + what, &normals, error))
      return false;
    if (normals.count != positions.count) return *error = what + ": NORMAL count differs from POSITION", false;
  }
  std::vector<std::vector<Influence>> influences;
  if (!read_influences(model, primitive, positions.count, palette.size(), what, &influences,
                       &out->renormalized_vertices, error))
    return false;
  for (size_t v = 0; v < positions.count; ++v) {
    Eigen::Matrix4d blended = Eigen::Matrix4d::Zero();
    for (const Influence& influence : influences[v]) blended += influence.weight * palette[influence.joint];
    const Eigen::Vector3d p(positions.at(v, 0), positions.at(v, 1), positions.at(v, 2));
    out->positions.emplace_back(blended.topLeftCorner<3, 3>() * p + blended.topRightCorner<3, 1>());
    if (*has_normals) {
      const Eigen::Vector3d n(normals.at(v, 0), normals.at(v, 1), normals.at(v, 2));
      out->normals.push_back(transform_normal(blended.topLeftCorner<3, 3>(), n));
    } else {
      out->normals.push_back(Eigen::Vector3d::Zero());
    }
  }
  return true;
}

}  // namespace

bool skin_model(const tinygltf::Model& model, const Matrices& world, SkinnedVertices* out, std::string* error) {
  *out = SkinnedVertices{};
  bool any_skinned = false, any_normals = false;
  for (size_t n = 0; n < model.nodes.size(); ++n) {
    const tinygltf::Node& node = model.nodes[n];
    if (node.mesh < 0 || node.skin < 0) continue;
    const std::string what = "node " + std::to_string(n);
    if (static_cast<size_t>(node.mesh) >= model.meshes.size())
      return *error = what + ": mesh " + std::to_string(node.mesh) + " does not exist", false;
    if (static_cast<size_t>(node.skin) >= model.skins.size())
      return *error = what + ": skin " + std::to_string(node.skin) + " does not exist", false;
    any_skinned = true;
    Matrices palette;
    if (!joint_matrices(model, node.skin, world, &palette, error)) return false;
    const tinygltf::Mesh& mesh = model.meshes[static_cast<size_t>(node.mesh)];
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      bool has_normals = false;
      const std::string primitive = what + " mesh " + std::to_string(node.mesh) + " primitive " + std::to_string(p);
      if (!skin_primitive(model, mesh.primitives[p], palette, primitive, out, &has_normals, error)) return false;
      any_normals = any_normals || has_normals;
    }
  }
  if (!any_skinned) return *error = "no skinned mesh (no node has both a mesh and a skin)", false;
  if (!any_normals) out->normals.clear();
  return true;
}

}  // namespace sinew::oracle::detail
