#pragma once
// Independent double-precision reference ("oracle") for glTF 2.0 skinning,
// used by tests to check sinew's fixed-point pipeline. It shares no code with
// the product: it reads the file with tinygltf and follows the glTF 2.0 spec
// directly (animation sampling, node hierarchy, linear blend skinning).
#include <Eigen/Core>
#include <string>
#include <vector>

namespace sinew::oracle {

struct OracleResult {
  // Skinned vertices: every node with both a mesh and a skin in model.nodes
  // order, every primitive of its mesh in order, every vertex in accessor
  // order. Skinned world space, file units.
  std::vector<Eigen::Vector3d> positions;
  // Unit normals (inverse transpose of each blended matrix), one per
  // position; (0,0,0) for primitives without NORMAL; empty if none has one.
  std::vector<Eigen::Vector3d> normals;
  // Diagonal of the axis-aligned bounding box of the REST pose: the skinned
  // positions with every node at its own (unanimated) transform. It does not
  // depend on the animation or time asked for, so it scales error tolerances.
  double bbox_diagonal = 0;
  // Vertices whose weights did not sum to 1 (beyond 1e-4) and were divided
  // by their sum. Weights are always divided by their sum.
  int renormalized_vertices = 0;
};

// Skinned vertices of the model at `path` (.gltf or .glb) with animation
// `animation` sampled at `time_seconds` (clamped by each sampler to its
// keyframes). animation == -1 gives the rest pose (no animation applied).
// Morph targets and "weights" channels are ignored. Zero-weight influences are
// skipped, so only joint indices that carry weight must be in range.
// Returns false with a message naming the problem.
bool skinned_pose(const std::string& path, int animation, double time_seconds, OracleResult* out, std::string* error);

// First and last keyframe time over all samplers of animation `animation`.
bool animation_time_range(const std::string& path, int animation, double* start, double* end, std::string* error);

// Number of animations in the file, or -1 (with *error set) if it cannot be read.
int animation_count(const std::string& path, std::string* error);

}  // namespace sinew::oracle
