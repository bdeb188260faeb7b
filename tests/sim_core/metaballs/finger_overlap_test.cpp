// Surface overlapping between two bones that share no joint
// (metaballs-pbd-skinning, "Surface overlapping": the ball sets of two bones
// detect their collision, and the vertices inside the colliding balls of the
// other bone are projected onto an interior plane). The built-in hand with
// the index and middle fingers spread toward each other, so their proximal
// phalanges press together; the check is written from the paper's statement
// in double: for every pair of balls of the two fingers that overlaps now
// but not at rest, no vertex of one finger following its ball lies inside
// the other finger's ball beyond the plane midway through the two balls.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "arm_scene.hpp"

namespace finger_overlap_test {
namespace {

using sinew::test::ArmScene;
namespace rigc = sinew::rigc;
namespace mb = sinew::metaballs;

constexpr double kFingerRadius = 0.0085;  // builtin_rigs.cpp, finger_radius

sinew::metaballs_build::Options hand_options() {
  sinew::metaballs_build::Options o;
  o.ball_spacing = 0.22 * kFingerRadius;  // the layer's default for the hand (rig_layers.cpp)
  return o;
}

struct Crossings {
  uint32_t beyond = 0;     // vertices inside a colliding ball of the other finger, beyond the plane
  double deepest = 0;      // m
  uint32_t colliding = 0;  // ball pairs overlapping now but not at rest
};

// The paper's condition, from the state and the output in double.
Crossings crossings(ArmScene& s, int bone_a, int bone_b) {
  const mb::MetaballModel& m = s.model();
  const mb::MetaballState& st = s.state();
  const auto centre = [&](uint32_t b) {
    return std::array<double, 3>{s.len(st.ball_center[b].x), s.len(st.ball_center[b].y), s.len(st.ball_center[b].z)};
  };
  const auto rest = [&](uint32_t b) {
    return std::array<double, 3>{s.len(m.ball_rest[b].x), s.len(m.ball_rest[b].y), s.len(m.ball_rest[b].z)};
  };
  const auto radius = [&](uint32_t b) { return s.len(m.ball_radius[b]) * std::ldexp(st.ball_scale[b], -30); };
  const auto dist = [](const std::array<double, 3>& p, const std::array<double, 3>& q) {
    return std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
  };
  Crossings out;
  const auto& bone_of_vertex = s.build().vertex_bone;
  for (uint32_t i = 0; i < m.ball_count(); ++i)
    for (uint32_t j = 0; j < m.ball_count(); ++j) {
      if (m.ball_bone[i] != bone_a && m.ball_bone[i] != bone_b) continue;
      if (m.ball_bone[j] == m.ball_bone[i] || (m.ball_bone[j] != bone_a && m.ball_bone[j] != bone_b)) continue;
      const double d = dist(centre(i), centre(j));
      if (d >= radius(i) + radius(j) || dist(rest(i), rest(j)) < s.len(m.ball_radius[i]) + s.len(m.ball_radius[j]))
        continue;
      if (i < j) ++out.colliding;
      // The plane midway through the overlap, normal toward ball i.
      const auto ci = centre(i), cj = centre(j);
      std::array<double, 3> n{}, o{};
      for (size_t k = 0; k < 3; ++k) n[k] = (ci[k] - cj[k]) / d;
      const double offset = (d + radius(j) - radius(i)) / 2;
      for (size_t k = 0; k < 3; ++k) o[k] = cj[k] + n[k] * offset;
      for (uint32_t v = 0; v < m.vertex_count; ++v) {
        if (m.vertex_ball[size_t{v} * mb::kVertexBalls] != i || bone_of_vertex[v] != static_cast<int>(m.ball_bone[i]))
          continue;
        const std::array<double, 3> p{s.mb(0, v), s.mb(1, v), s.mb(2, v)};
        if (dist(p, cj) >= radius(j)) continue;
        const double side = (p[0] - o[0]) * n[0] + (p[1] - o[1]) * n[1] + (p[2] - o[2]) * n[2];
        // A projected vertex lies on the plane to the rounding of its Len
        // coordinates and of the plane's (a few LSB): 8 LSB.
        if (side < -8 * s.len(1)) {
          ++out.beyond;
          out.deepest = std::max(out.deepest, -side);
        }
      }
    }
  return out;
}

TEST(MetaballsFingerOverlap, SpreadFingersMeetOnTheInteriorPlane) {
  ArmScene s(rigc::builtin_hand(), hand_options());
  ASSERT_TRUE(s.ok()) << s.error();
  const int index = rigc::joint_index(s.spec(), "index_mcp"), middle = rigc::joint_index(s.spec(), "middle_mcp");
  size_t records = 0, all = 0, balls = 0, vertices = 0;
  for (const auto& r : s.model().overlaps) {
    if (r.joint != mb::kNoJoint) continue;
    ++all;
    balls += r.balls_b_end - r.balls_a_begin;
    vertices += r.vertices_b_end - r.vertices_a_begin;
  }
  std::printf("hand: %zu records of bones sharing no joint, %zu balls and %zu vertices listed\n", all, balls, vertices);
  for (const auto& r : s.model().overlaps)
    if (r.joint == mb::kNoJoint &&
        ((r.bone_a == index && r.bone_b == middle) || (r.bone_a == middle && r.bone_b == index)))
      ++records;
  ASSERT_EQ(records, 1u) << "the proximal phalanges of neighbouring fingers can meet: one record";
  // Rest: no ball of one finger collides with one of the other, so the
  // record leaves the rest skin alone.
  ASSERT_TRUE(s.pose_dofs({}));
  EXPECT_EQ(crossings(s, index, middle).colliding, 0u);
  // Spread toward each other by 8 degrees each (the abduction DOF, +-20):
  // the axes, 18 mm apart at the knuckles, close to 5.5 mm at the PIP.
  const std::vector<ArmScene::DofAngle> spread = {{"index_mcp", 1, 8.0}, {"middle_mcp", 1, -8.0}};
  s.state().features.overlap = false;
  ASSERT_TRUE(s.pose_dofs(spread));
  const Crossings without = crossings(s, index, middle);
  s.state().features.overlap = true;
  ASSERT_TRUE(s.pose_dofs(spread));
  const Crossings with = crossings(s, index, middle);
  std::printf(
      "finger overlap, index and middle spread 8 deg toward each other: %u colliding ball pairs; vertices beyond "
      "the interior plane %u (deepest %.2f mm) without handling, %u (deepest %.2f mm) with; %u projected\n",
      without.colliding, without.beyond, without.deepest * 1e3, with.beyond, with.deepest * 1e3,
      s.state().stats.projected_vertices);
  EXPECT_GT(without.colliding, 0u);
  EXPECT_GT(without.beyond, 0u) << "the pose should press the fingers together";
  EXPECT_EQ(with.beyond, 0u);
  EXPECT_GT(s.state().stats.projected_vertices, 0u);
}

// The rest pose is the rest mesh: overlap is a collision of the posed ball
// sets, so at rest the stage moves nothing, on the arm and on the hand
// (whose knuckles start inside the palm's balls).
TEST(MetaballsFingerOverlap, RestPoseIsLeftAlone) {
  for (const bool hand : {false, true}) {
    ArmScene s(hand ? rigc::builtin_hand() : rigc::builtin_arm(rigc::SkinChoice::kDualQuaternion),
               hand ? hand_options() : sinew::test::arm_options());
    ASSERT_TRUE(s.ok()) << s.error();
    ASSERT_TRUE(s.pose_dofs({}));
    const uint32_t projected = s.state().stats.projected_vertices;
    std::vector<int32_t> with[3];
    for (int a = 0; a < 3; ++a)
      for (uint32_t v = 0; v < s.model().vertex_count; ++v) with[a].push_back(s.output().position[a][v]);
    s.state().features.overlap = false;
    ASSERT_TRUE(s.pose_dofs({}));
    uint32_t moved = 0;
    for (int a = 0; a < 3; ++a)
      for (uint32_t v = 0; v < s.model().vertex_count; ++v) moved += with[a][v] != s.output().position[a][v] ? 1u : 0u;
    std::printf("%s at rest: %u vertices projected, %u coordinates moved by the overlap stage\n", hand ? "hand" : "arm",
                projected, moved);
    EXPECT_EQ(projected, 0u);
    EXPECT_EQ(moved, 0u);
  }
}

}  // namespace
}  // namespace finger_overlap_test
