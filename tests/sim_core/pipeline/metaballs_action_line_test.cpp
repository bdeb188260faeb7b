// Action lines through the whole pipeline (metaballs-pbd-skinning: "we couple
// our metaballs model with position-based dynamics and action lines"): a rig
// compiled with a biceps-like line (MBAL version 2) and loaded from its blob
// as the daemon loads it, stepped while the elbow bends: the line's balls keep
// their rest distance from the point of the line between its two endpoints,
// which ride on the upper arm and the forearm; with the line switched off
// they do not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "host_tools/rigc/builtin_rigs.hpp"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"

namespace pl = sinew::pipeline;

namespace {

constexpr uint32_t kActionElbowInput = 3;  // shoulder 0..2, elbow 3 (about +z)
constexpr double kActionPi = 3.14159265358979323846;

std::unique_ptr<sinew::test::LoadedLayers> arm_with_biceps_line(std::string* error) {
  sinew::layers::LayerSpecs tables;
  tables.metaballs.on = true;
  tables.metaballs.where = "action line test: [metaballs]";
  sinew::metaballs_build::ActionLineSpec line;
  line.origin = "shoulder";  // 0.3 along the upper arm
  line.origin_at = 0.3;
  line.insertion = "elbow";  // 0.3 along the forearm
  line.insertion_at = 0.3;
  line.side[1] = 0.03;  // +y: the inner side of the elbow's flexion about +z
  line.reach = 0.04;    // the balls on the bone axes, 3 cm from the line
  line.stiffness = 1.0;
  tables.metaballs.options.action_lines.push_back(line);
  return sinew::test::compiled_with_layers(sinew::rigc::builtin_arm(sinew::rigc::SkinChoice::kDualQuaternion), tables,
                                           error);
}

struct Point {
  double x = 0, y = 0, z = 0;
};

// p turned by phi about the z axis through `pivot`.
Point turned_about_z(Point p, Point pivot, double phi) {
  const double c = std::cos(phi), s = std::sin(phi), dx = p.x - pivot.x, dy = p.y - pivot.y;
  return {pivot.x + c * dx - s * dy, pivot.y + s * dx + c * dy, p.z};
}

double point_distance(Point a, Point b) { return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z); }

TEST(MetaballsActionLinePipeline, BallsFollowTheLineEndpointsAsTheElbowBends) {
  std::string error;
  auto on = arm_with_biceps_line(&error);
  ASSERT_NE(on, nullptr) << error;
  auto off = arm_with_biceps_line(&error);
  ASSERT_NE(off, nullptr) << error;
  pl::PipelineOptions options;
  ASSERT_TRUE(on->start(options, &error)) << error;
  ASSERT_TRUE(off->start(options, &error)) << error;
  off->pipeline.metaballs.state.features.action_lines = false;
  const auto& model = on->layers.metaballs.model;
  ASSERT_EQ(model.action_lines.size(), 1u);
  ASSERT_FALSE(model.action_balls.empty());
  const double lsb = std::ldexp(1.0, on->rig.length_exponent - sinew::fx::kLenFracBits);
  const auto metres = [&](const sinew::fx::Vec3& v) { return Point{lsb * v.x, lsb * v.y, lsb * v.z}; };
  const auto& line = model.action_lines[0];
  ASSERT_EQ(line.origin_bone, 0);     // the upper arm: still (only the elbow turns)
  ASSERT_EQ(line.insertion_bone, 1);  // the forearm: turns about the elbow
  const Point origin = metres(line.origin_rest);
  const Point elbow = {lsb * on->pipeline.engine.model[1].t[0], lsb * on->pipeline.engine.model[1].t[1],
                       lsb * on->pipeline.engine.model[1].t[2]};
  const Point twist_rest = {lsb * on->pipeline.engine.model[2].t[0], lsb * on->pipeline.engine.model[2].t[1],
                            lsb * on->pipeline.engine.model[2].t[2]};
  // The line point of an action ball, from the endpoints' geometry alone:
  // the origin stays, the insertion turns with the forearm by phi.
  const auto line_point = [&](const sinew::pipeline::LayerSet& set, size_t k, double phi) {
    const Point insertion = turned_about_z(metres(set.metaballs.model.action_lines[0].insertion_rest), elbow, phi);
    const double t = std::ldexp(set.metaballs.model.action_balls[k].along, -30);
    return Point{origin.x + t * (insertion.x - origin.x), origin.y + t * (insertion.y - origin.y),
                 origin.z + t * (insertion.z - origin.z)};
  };
  // |C| = | |c - L| - rest | over the line's balls.
  const auto worst_constraint = [&](const sinew::test::LoadedLayers& arm, double phi) {
    double worst = 0;
    for (size_t k = 0; k < model.action_balls.size(); ++k) {
      const auto& a = model.action_balls[k];
      const Point c = metres(arm.pipeline.metaballs.state.ball_center[a.ball]);
      worst = std::max(worst, std::fabs(point_distance(c, line_point(arm.layers, k, phi)) - lsb * a.rest));
    }
    return worst;
  };
  // The line's projection comes last in each sweep with stiffness 1: C is
  // left at the rounding of one projection (normalize_fast: a direction
  // within ~4 LSB of unit length, so a few LSB of the move) plus the
  // fixed-point endpoints against this double geometry (the Q2.30 rotation
  // on a ~5 cm lever and the transforms' rounding: a few LSB). 16 LSB.
  const double bound_on = 16 * lsb;
  // Without the line the balls follow their bones, while the line's point
  // moves t 2 |I - E| sin(phi / 2) relative to the upper arm: centimetres
  // at these bends, so their distances to it change by millimetres.
  constexpr double kOffAtLeast = 1e-3;
  std::vector<int32_t> inputs(on->pipeline.input_count, 0);
  constexpr int kTicks = 540;  // 0.54 s at 1 kHz: 0 to 135 degrees
  double worst_on = 0, least_off = 1, moved_skin = 0;
  for (int n = 1; n <= kTicks; ++n) {
    const double degrees = 135.0 * n / kTicks;
    inputs[kActionElbowInput] = sinew::test::degrees(degrees);
    for (auto* arm : {on.get(), off.get()}) {
      const pl::PipelineStatus st = pl::pipeline_step(&arm->pipeline, inputs);
      ASSERT_TRUE(st.ok()) << st.message;
    }
    if (n % 60 != 0) continue;
    const double phi = degrees * kActionPi / 180;
    // The oracle's turn is the engine's: the next joint rides on the forearm.
    const Point twist = turned_about_z(twist_rest, elbow, phi);
    const auto& t = on->pipeline.engine.model[2].t;
    ASSERT_LT(point_distance(twist, {lsb * t[0], lsb * t[1], lsb * t[2]}), 4 * lsb) << degrees;
    const double with = worst_constraint(*on, phi), without = worst_constraint(*off, phi);
    double moved = 0;  // the line's effect on the pipeline's output skin
    for (uint32_t v = 0; v < on->rig.vertex_count(); ++v) {
      const auto& a = on->pipeline.engine.vertices.position;
      const auto& b = off->pipeline.engine.vertices.position;
      moved = std::max(moved,
                       lsb * std::hypot(static_cast<double>(a[0][v] - b[0][v]), static_cast<double>(a[1][v] - b[1][v]),
                                        static_cast<double>(a[2][v] - b[2][v])));
    }
    std::printf(
        "action line in the pipeline: elbow %.0f deg, %zu balls: largest |C| %.3g m with it (bound %.3g), %.3g m "
        "without; skin moved up to %.3g m\n",
        degrees, model.action_balls.size(), with, bound_on, without, moved);
    worst_on = std::max(worst_on, with);
    if (degrees >= 45) least_off = std::min(least_off, without), moved_skin = std::max(moved_skin, moved);
  }
  EXPECT_LE(worst_on, bound_on);
  EXPECT_GT(least_off, kOffAtLeast);
  EXPECT_GT(least_off, 10 * bound_on);
  EXPECT_GT(moved_skin, 1e-4);  // the balls' shift reaches the skin the pipeline outputs
}

}  // namespace
