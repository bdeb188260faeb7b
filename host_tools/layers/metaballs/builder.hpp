// Offline builder of the metaballs layer: a rig spec (mesh + skeleton +
// skin weights) -> a fixed-point MetaballModel. Doubles are used here only
// with + - * / and sqrt (correctly rounded), and the library is compiled
// with -ffp-contract=off, so the model is bit-identical on every platform.
//
//   balls:     centres along each bone, radius = distance to the nearest
//              vertex, bone weights w^beta averaged from the skin weights of
//              the nearest vertices (top two joints);
//   pairs:     balls closer than pair_reach * (r_a + r_b);
//   vertices:  w^gamma over the kVertexBalls nearest balls of the bones the
//              vertex is skinned to, displacements d = v - c (exact integers,
//              so the rest pose reproduces the rest mesh);
//   joints:    joint balls, their region weights w^alpha, rotation blends,
//              rest Laplacians and neighbours; overlap candidates.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host_tools/rigc/rig_spec.hpp"
#include "options.hpp"
#include "sim_core/metaballs/model.hpp"

namespace sinew::metaballs_build {

// Owns every array of a model; model() returns spans into it.
struct Build {
  int32_t length_exponent = 0;  // the rig's (rigc::choose_length_exponent)
  uint32_t joint_count = 0, vertex_count = 0;
  std::vector<fx::Mat34> inverse_bind;
  std::vector<fx::Vec3> ball_rest;
  std::vector<fx::Len> ball_radius;
  std::vector<uint16_t> ball_bone, ball_joint;
  std::vector<fx::Unit> ball_weight, ball_jiggle;
  std::vector<metaballs::BallPair> pairs;
  std::vector<metaballs::BulgeRecord> bulges;
  std::vector<metaballs::ActionLine> action_lines;
  std::vector<metaballs::ActionBall> action_balls;
  uint32_t pbd_iterations = 0;
  fx::Unit jiggle_damping = 0;
  uint32_t jiggle_rate_hz = 0;  // > 0: physical jiggle gains for this rate
  std::vector<uint16_t> vertex_ball;
  std::vector<fx::Unit> vertex_weight;
  std::vector<fx::Vec3> vertex_disp;
  std::vector<metaballs::JointBall> joint_balls;
  std::vector<uint32_t> jv_vertex;
  std::vector<uint16_t> jv_ball;
  std::vector<fx::Unit> jv_alpha, jv_blend;
  std::vector<fx::Vec3> jv_disp, jv_laplacian;
  std::vector<uint32_t> jv_neighbour_begin, jv_neighbours;
  std::vector<fx::Unit> jv_inv_count;
  uint32_t smoothing_passes = 0;
  fx::Unit smoothing_rate = 0;
  std::vector<metaballs::OverlapRecord> overlaps;
  std::vector<uint32_t> overlap_vertices;
  std::vector<uint16_t> overlap_balls;

  // Builder-side facts for tests and reports (not part of the model).
  std::vector<double> ball_along;  // position along its bone, [0, 1]
  std::vector<int> vertex_bone;    // dominant bone of each vertex

  metaballs::MetaballModel model() const;
};

// Returns false with a message naming the problem (option field, bone name).
bool build(const rigc::RigSpec& spec, const Options& options, Build* out, std::string* error);

std::string summary(const Build& b);

}  // namespace sinew::metaballs_build
