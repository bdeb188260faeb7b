#include "gltf_oracle.hpp"

#include "animation_sampler.hpp"
#include "gltf_model.hpp"
#include "node_transforms.hpp"
#include "skinning.hpp"

namespace sinew::oracle {
namespace {

double bbox_diagonal(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) return 0;
  Eigen::Vector3d low = points.front(), high = points.front();
  for (const Eigen::Vector3d& p : points) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  return (high - low).norm();
}

bool skin_with_poses(const tinygltf::Model& model, const detail::NodePoses& poses, detail::SkinnedVertices* out,
                     std::string* error) {
  detail::Matrices world;
  return detail::world_transforms(model, poses, &world, error) && detail::skin_model(model, world, out, error);
}

}  // namespace

bool skinned_pose(const std::string& path, int animation, double time_seconds, OracleResult* out, std::string* error) {
  tinygltf::Model model;
  if (!detail::load_model(path, &model, error)) return false;
  if (animation < -1 || animation >= static_cast<int>(model.animations.size())) {
    *error = path + ": animation " + std::to_string(animation) + " out of range (the file has " +
             std::to_string(model.animations.size()) + " animations)";
    return false;
  }
  detail::NodePoses poses;
  detail::SkinnedVertices rest;
  if (!detail::default_node_poses(model, &poses, error) || !skin_with_poses(model, poses, &rest, error)) {
    *error = path + ": " + *error;
    return false;
  }
  out->bbox_diagonal = bbox_diagonal(rest.positions);
  out->renormalized_vertices = rest.renormalized_vertices;
  if (animation < 0) {
    out->positions = std::move(rest.positions);
    out->normals = std::move(rest.normals);
    return true;
  }
  detail::SkinnedVertices posed;
  if (!detail::apply_animation(model, animation, time_seconds, &poses, error) ||
      !skin_with_poses(model, poses, &posed, error)) {
    *error = path + ": " + *error;
    return false;
  }
  out->positions = std::move(posed.positions);
  out->normals = std::move(posed.normals);
  return true;
}

bool animation_time_range(const std::string& path, int animation, double* start, double* end, std::string* error) {
  tinygltf::Model model;
  if (!detail::load_model(path, &model, error)) return false;
  if (!detail::animation_range(model, animation, start, end, error)) {
    *error = path + ": " + *error;
    return false;
  }
  return true;
}

int animation_count(const std::string& path, std::string* error) {
  tinygltf::Model model;
  if (!detail::load_model(path, &model, error)) return -1;
  return static_cast<int>(model.animations.size());
}

}  // namespace sinew::oracle
