// Action lines (metaballs-pbd-skinning, "we couple our metaballs model with
// position-based dynamics and action lines"): a biceps-like line from the
// upper arm to the forearm, on the inner side of the bend, constrains the
// balls near it to keep their rest distance from it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "arm_scene.hpp"

namespace {

using sinew::test::ArmScene;
namespace mbb = sinew::metaballs_build;
namespace rigc = sinew::rigc;

mbb::Options biceps_line_options() {
  mbb::Options o = sinew::test::arm_options();
  mbb::ActionLineSpec l;
  l.origin = "shoulder";  // the upper arm
  l.origin_at = 0.3;
  l.insertion = "elbow";  // the forearm
  l.insertion_at = 0.3;
  l.side[1] = 0.03;  // +y: the inner side of elbow flexion (about +z)
  l.reach = 0.04;    // the balls lie on the bone axes, 3 cm from the line
  l.stiffness = 1.0;
  o.action_lines.push_back(l);
  return o;
}

// Largest |C| = | |c - L(along)| - rest | over the line's balls, in metres.
double worst_constraint(ArmScene& s) {
  const auto& m = s.model();
  const auto& st = s.state();
  double worst = 0;
  for (const auto& a : m.action_balls) {
    const auto& line = m.action_lines[a.line];
    const auto o = sinew::fx::transform_point(st.bone[line.origin_bone], line.origin_rest);
    const auto i = sinew::fx::transform_point(st.bone[line.insertion_bone], line.insertion_rest);
    const double t = std::ldexp(a.along, -30);
    const double p[3] = {s.len(o.x) + t * (s.len(i.x) - s.len(o.x)), s.len(o.y) + t * (s.len(i.y) - s.len(o.y)),
                         s.len(o.z) + t * (s.len(i.z) - s.len(o.z))};
    const auto& c = st.ball_center[a.ball];
    const double d =
        std::sqrt(std::pow(s.len(c.x) - p[0], 2) + std::pow(s.len(c.y) - p[1], 2) + std::pow(s.len(c.z) - p[2], 2));
    worst = std::max(worst, std::fabs(d - s.len(a.rest)));
  }
  return worst;
}

TEST(MetaballsActionLines, RestPoseUnchanged) {
  ArmScene s(rigc::SkinChoice::kDualQuaternion, biceps_line_options());
  ASSERT_TRUE(s.ok()) << s.error();
  ASSERT_FALSE(s.model().action_balls.empty());
  ASSERT_TRUE(s.pose(0, 0, 0));
  double worst = 0;
  for (uint32_t v = 0; v < s.rig().vertex_count(); ++v)
    for (int a = 0; a < 3; ++a) worst = std::max(worst, std::fabs(s.mb(a, v) - s.rest(a, v)));
  EXPECT_LT(worst, 2e-6);  // as without action lines (volume_test): C = 0 at rest
}

TEST(MetaballsActionLines, BallsKeepTheirDistanceToTheLineAsTheElbowBends) {
  ArmScene on(rigc::SkinChoice::kDualQuaternion, biceps_line_options()),
      off(rigc::SkinChoice::kDualQuaternion, biceps_line_options());
  ASSERT_TRUE(on.ok() && off.ok()) << on.error();
  off.state().features.action_lines = false;
  for (double elbow : {45.0, 90.0, 135.0}) {
    ASSERT_TRUE(on.pose(0, elbow, 0));
    ASSERT_TRUE(off.pose(0, elbow, 0));
    double moved = 0;  // how far the skin moved because of the line
    for (uint32_t v = 0; v < on.rig().vertex_count(); ++v)
      moved = std::max(moved,
                       std::hypot(on.mb(0, v) - off.mb(0, v), on.mb(1, v) - off.mb(1, v), on.mb(2, v) - off.mb(2, v)));
    const double with = worst_constraint(on), without = worst_constraint(off);
    std::printf(
        "action line: elbow %.0f deg, %zu balls on the line: largest |C| %.3g m with it, %.3g m without; skin moved "
        "up to %.3g m\n",
        elbow, on.model().action_balls.size(), with, without, moved);
    // Stiffness 1 and the line's projection last in each sweep: C is left
    // at the rounding of one projection (a few Len LSB, ~1e-6 m here).
    EXPECT_LT(with, 1e-5);
    // Without the line the bend changes those distances by millimetres.
    EXPECT_GT(without, 1e-3);
    EXPECT_GT(moved, 1e-4);
  }
}

}  // namespace
