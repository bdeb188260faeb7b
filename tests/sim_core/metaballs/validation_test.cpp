// Bad data is rejected with a message naming the field: the model validator,
// init, the step's span checks, and the builder's options.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <string>

#include "arm_scene.hpp"
#include "sim_core/metaballs/validate.hpp"

namespace {

namespace mb = sinew::metaballs;
namespace mbb = sinew::metaballs_build;
namespace rigc = sinew::rigc;

const mbb::Build& arm_build() {
  static const mbb::Build b = [] {
    mbb::Options o = sinew::test::arm_options();
    // Per-step jiggle: its stretch pairs (a jiggle ball's) are the model's
    // only pairs, which the corruptions below need.
    o.jiggle_frequency = 0;
    o.jiggle.push_back({"shoulder", 0.3, 0.7, 0.1});
    o.bulge.push_back({"shoulder", 0.3, 0.7, "shoulder", "elbow", 0.3});
    mbb::Build out;
    std::string error;
    if (!mbb::build(rigc::builtin_arm(), o, &out, &error)) std::printf("build failed: %s\n", error.c_str());
    return out;
  }();
  return b;
}

void expect_rejected(const char* what, const std::function<void(mbb::Build&)>& corrupt, mb::LayerError error,
                     const char* field) {
  mbb::Build b = arm_build();
  corrupt(b);
  const mb::LayerStatus s = mb::metaballs_validate_model(b.model());
  std::printf("validate, %s: %s: %s\n", what, sinew::layer::layer_error_name(s.error), s.message);
  EXPECT_EQ(s.error, error) << what;
  EXPECT_NE(std::string(s.message).find(field), std::string::npos) << what << ": " << s.message;
}

}  // namespace

TEST(MetaballsValidate, AcceptsTheBuiltModel) {
  const mb::LayerStatus s = mb::metaballs_validate_model(arm_build().model());
  EXPECT_TRUE(s.ok()) << s.message;
}

TEST(MetaballsValidate, RejectsEachKindOfBadData) {
  using E = mb::LayerError;
  expect_rejected(
      "no joints", [](mbb::Build& b) { b.joint_count = 0; }, E::kBadCount, "joint_count");
  expect_rejected(
      "inverse binds short", [](mbb::Build& b) { b.inverse_bind.pop_back(); }, E::kBadSize, "inverse_bind");
  expect_rejected(
      "radius array short", [](mbb::Build& b) { b.ball_radius.pop_back(); }, E::kBadSize, "ball_radius");
  expect_rejected(
      "zero radius", [](mbb::Build& b) { b.ball_radius[3] = 0; }, E::kBadValue, "ball_radius[3]");
  expect_rejected(
      "ball bone index", [](mbb::Build& b) { b.ball_bone[2] = 99; }, E::kBadIndex, "ball_bone[2]");
  expect_rejected(
      "ball weights sum", [](mbb::Build& b) { b.ball_weight[0] -= 1; }, E::kBadValue, "ball_weight");
  expect_rejected(
      "ball joint index", [](mbb::Build& b) { b.ball_joint[1] = 7; }, E::kBadIndex, "ball_joint[1]");
  expect_rejected(
      "jiggle stiffness", [](mbb::Build& b) { b.ball_jiggle[0] = -5; }, E::kBadValue, "ball_jiggle[0]");
  expect_rejected(
      "self pair", [](mbb::Build& b) { b.pairs[0].b = b.pairs[0].a; }, E::kBadIndex, "pairs.b[0]");
  expect_rejected(
      "pair shares", [](mbb::Build& b) { b.pairs[1].share_a += 1; }, E::kBadValue, "pairs.share");
  expect_rejected(
      "pair rest", [](mbb::Build& b) { b.pairs[2].rest = 0; }, E::kBadValue, "pairs.rest[2]");
  expect_rejected(
      "bulge gain", [](mbb::Build& b) { b.bulges[0].gain = 1 << 30; }, E::kBadValue, "bulges.gain[0]");
  expect_rejected(
      "iterations", [](mbb::Build& b) { b.pbd_iterations = 17; }, E::kBadValue, "pbd_iterations");
  expect_rejected(
      "damping", [](mbb::Build& b) { b.jiggle_damping = 1 << 30; }, E::kBadValue, "jiggle_damping");
  expect_rejected(
      "vertex weights sum", [](mbb::Build& b) { b.vertex_weight[8] += 3; }, E::kBadValue, "vertex_weight");
  expect_rejected(
      "vertex ball index", [](mbb::Build& b) { b.vertex_ball[0] = 4000; }, E::kBadIndex, "vertex_ball[0]");
  expect_rejected(
      "displacement range", [](mbb::Build& b) { b.vertex_disp[5].y = INT32_MAX; }, E::kBadValue, "vertex_disp[5]");
  expect_rejected(
      "joint-region order", [](mbb::Build& b) { b.jv_vertex[1] = b.jv_vertex[0]; }, E::kBadIndex, "jv_vertex[1]");
  expect_rejected(
      "joint-region alpha", [](mbb::Build& b) { b.jv_alpha[0] = 0; }, E::kBadValue, "jv_alpha[0]");
  expect_rejected(
      "neighbour index", [](mbb::Build& b) { b.jv_neighbours[4] = 1u << 30; }, E::kBadIndex, "jv_neighbours[4]");
  expect_rejected(
      "neighbour reciprocal", [](mbb::Build& b) { b.jv_inv_count[0] += 1; }, E::kBadValue, "jv_inv_count[0]");
  expect_rejected(
      "smoothing passes", [](mbb::Build& b) { b.smoothing_passes = 9; }, E::kBadValue, "smoothing_passes");
  expect_rejected(
      "overlap direction",
      [](mbb::Build& b) {
        b.overlaps[0].dir_a = {1 << 29, 0, 0};
      },
      E::kBadValue, "overlaps.dir_a[0]");
  expect_rejected(
      "overlap range", [](mbb::Build& b) { b.overlaps[0].balls_b_end = 1u << 20; }, E::kBadIndex, "overlaps.balls[0]");
  expect_rejected(
      "overlap of a bone with itself",
      [](mbb::Build& b) {
        mb::OverlapRecord r{};
        r.joint = mb::kNoJoint;
        b.overlaps.push_back(r);  // bone_a == bone_b == 0
      },
      E::kBadIndex, "bone_a again");
}

TEST(MetaballsValidate, InitRejectsBadMemory) {
  const mbb::Build& b = arm_build();
  const mb::MetaballModel m = b.model();
  std::vector<uint64_t> memory(mb::metaballs_state_bytes(m) / 8 + 2, 0);
  mb::MetaballState st;
  mb::LayerStatus s = mb::metaballs_init(m, memory.data(), mb::metaballs_state_bytes(m) - 8, &st);
  std::printf("init, short memory: %s\n", s.message);
  EXPECT_EQ(s.error, mb::LayerError::kArena);
  s = mb::metaballs_init(m, reinterpret_cast<uint8_t*>(memory.data()) + 4, memory.size() * 8 - 4, &st);
  std::printf("init, misaligned memory: %s\n", s.message);
  EXPECT_EQ(s.error, mb::LayerError::kArena);
  mbb::Build bad = b;
  bad.ball_radius[0] = -1;
  const mb::MetaballModel bad_model = bad.model();
  s = mb::metaballs_init(bad_model, memory.data(), memory.size() * 8, &st);
  EXPECT_EQ(s.error, mb::LayerError::kBadValue) << "init validates the model";
}

TEST(MetaballsValidate, StepRejectsBadSpansAndChangesNothing) {
  sinew::test::ArmScene s;
  ASSERT_TRUE(s.ok()) << s.error();
  ASSERT_TRUE(s.pose(0, 30, 0));
  const uint64_t steps = s.state().stats.steps;
  mb::LayerStatus st = mb::metaballs_step(&s.state(), s.engine().model.first(2), s.output());
  std::printf("step, two joint transforms for a 4-joint model: %s\n", st.message);
  EXPECT_EQ(st.error, mb::LayerError::kBadSize);
  EXPECT_NE(std::string(st.message).find("joint_model"), std::string::npos);
  sinew::skin::SkinnedVertices out = s.output();
  out.position[2] = out.position[2].first(10);
  st = mb::metaballs_step(&s.state(), s.engine().model, out);
  std::printf("step, short output: %s\n", st.message);
  EXPECT_EQ(st.error, mb::LayerError::kBadSize);
  EXPECT_NE(std::string(st.message).find("out.position[2]"), std::string::npos);
  mb::MetaballState fresh;
  st = mb::metaballs_step(&fresh, s.engine().model, s.output());
  std::printf("step, uninitialised state: %s\n", st.message);
  EXPECT_EQ(st.error, mb::LayerError::kNotReady);
  EXPECT_EQ(s.state().stats.steps, steps);
}

TEST(MetaballsBuilder, RejectsBadOptionsNamingTheField) {
  struct Case {
    const char* field;
    std::function<void(mbb::Options&)> corrupt;
  };
  const Case cases[] = {
      {"ball_spacing", [](mbb::Options& o) { o.ball_spacing = 0; }},
      {"target_ball_count", [](mbb::Options& o) { o.target_ball_count = -1; }},
      {"weight_power", [](mbb::Options& o) { o.weight_power = 0; }},
      {"stretch_stiffness", [](mbb::Options& o) { o.stretch_stiffness = 1.5; }},
      {"pbd_iterations", [](mbb::Options& o) { o.pbd_iterations = 40; }},
      {"jiggle_damping", [](mbb::Options& o) { o.jiggle_damping = 1.0; }},
      {"jiggle[0].stiffness",
       [](mbb::Options& o) {
         o.jiggle.push_back({"shoulder", 0, 1, 0.0});
       }},
      {"jiggle[0].from/to",
       [](mbb::Options& o) {
         o.jiggle.push_back({"shoulder", 0.8, 0.2, 0.1});
       }},
      {"jiggle[0].bone",
       [](mbb::Options& o) {
         o.jiggle.push_back({"tail", 0, 1, 0.1});
       }},
      {"bulge[0].gain",
       [](mbb::Options& o) {
         o.bulge.push_back({"shoulder", 0, 1, "shoulder", "elbow", 1.0});
       }},
      {"bulge[0].angle_b",
       [](mbb::Options& o) {
         o.bulge.push_back({"shoulder", 0, 1, "shoulder", "knee", 0.2});
       }},
      {"bulge[0].angle_a/angle_b",
       [](mbb::Options& o) {
         o.bulge.push_back({"shoulder", 0, 1, "elbow", "elbow", 0.2});
       }},
      {"joint_inner/joint_outer", [](mbb::Options& o) { o.joint_outer = 0.5; }},
      {"joint_balls[0].name", [](mbb::Options& o) { o.joint_balls = {"shoulder"}; }},
      {"smoothing_passes", [](mbb::Options& o) { o.smoothing_passes = 99; }},
      {"smoothing_rate", [](mbb::Options& o) { o.smoothing_rate = -0.1; }},
      {"overlap_reach", [](mbb::Options& o) { o.overlap_reach = -1; }},
  };
  const rigc::RigSpec arm = rigc::builtin_arm();
  for (const Case& c : cases) {
    mbb::Options o = sinew::test::arm_options();
    c.corrupt(o);
    mbb::Build b;
    std::string error;
    EXPECT_FALSE(mbb::build(arm, o, &b, &error)) << c.field;
    std::printf("builder rejects %s: %s\n", c.field, error.c_str());
    EXPECT_EQ(error.rfind(c.field, 0), 0u) << error;
  }
}

// Any caller-provided transforms, however wrong, give defined results: every
// narrowing saturates (UBSan runs this in the dev build).
TEST(MetaballsValidate, StepIsTotalOnArbitraryTransforms) {
  sinew::test::ArmScene s;
  ASSERT_TRUE(s.ok()) << s.error();
  std::vector<sinew::fx::Mat34> garbage(s.model().joint_count);
  uint64_t x = 0x9E3779B97F4A7C15ull;
  const auto next = [&x] {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;  // xorshift64
    return static_cast<int32_t>(static_cast<uint32_t>(x >> 32));
  };
  uint32_t projected = 0;
  for (int step = 0; step < 50; ++step) {
    for (auto& t : garbage) {
      for (auto& row : t.m)
        for (auto& e : row) e = step % 2 == 0 ? next() : next() >> (step % 31);
      for (auto& e : t.t) e = next();
    }
    const mb::LayerStatus st = mb::metaballs_step(&s.state(), garbage, s.output());
    ASSERT_TRUE(st.ok()) << st.message;
    projected += s.state().stats.projected_vertices;
  }
  std::printf("step on 50 sets of random transforms: defined results, %u overlap projections\n", projected);
}
