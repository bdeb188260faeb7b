// The elbow bar-net on the built-in arm: the bind pose is reproduced, the
// bulge grows with flexion and the net restores the volume smooth skinning
// loses, a step never allocates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "arm_metrics.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/soak.hpp"

namespace bn = sinew::barnet;
using sinew::layers::barnet::ArmSession;
using sinew::layers::barnet::degrees_to_angle;
using namespace sinew::test::barnet;

namespace {

double distance(Point a, Point b) { return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z); }

}  // namespace

TEST(BarnetArm, BindPoseReproducesTheRestSkin) {
  ArmSession s;
  ASSERT_TRUE(s.ok()) << s.error();
  ASSERT_TRUE(s.step());
  int64_t worst_node = 0;
  for (uint32_t i = 0; i < s.model().nodes.size(); ++i) {
    const sinew::fx::Vec3 r = s.model().nodes[i].rest;
    const int32_t got[3] = {s.outputs().node[0][i], s.outputs().node[1][i], s.outputs().node[2][i]};
    const int32_t want[3] = {r.x, r.y, r.z};
    for (int c = 0; c < 3; ++c) worst_node = std::max<int64_t>(worst_node, std::llabs(int64_t{got[c]} - want[c]));
  }
  // Each wrapped vertex is bary . (a, b, c) + offset n: off by its nodes'
  // error (the 2 LSB above plus the builder's 0.5 LSB rounding, weighted by
  // |bary|), the Q2.30 barycentrics (2^-31 x |node|), the unit normal's few
  // 2^-30 times the offset, the offset's and the output's rounding (0.5 LSB
  // each), on each of three axes (sqrt 3 for the distance).
  double worst_skin = 0, worst_ratio = 0;
  for (uint32_t w = 0; w < s.model().wrap.size(); ++w) {
    const bn::WrapRecord& r = s.model().wrap[w];
    double bary = 0, node = 0;
    for (int k = 0; k < 3; ++k) {
      bary += std::abs(std::ldexp(r.bary[k], -30));
      const sinew::fx::Vec3 p = s.model().nodes[s.model().triangles[r.triangle].node[k]].rest;
      node = std::max({node, std::abs(s.metres(p.x)), std::abs(s.metres(p.y)), std::abs(s.metres(p.z))});
    }
    const double bound = std::sqrt(3.0) * (s.metres(1) * (2.5 * bary + 1.0) + 3 * node * 0x1p-31 +
                                           std::abs(s.metres(r.offset)) * 0x1p-27);
    const double d = distance(wrapped(s, w), rest(s, w));
    worst_skin = std::max(worst_skin, d);
    worst_ratio = std::max(worst_ratio, d / bound);
  }
  std::printf(
      "barnet arm: bind pose: %zu nodes (%u free), largest node deviation %lld LSB; %zu wrapped vertices, "
      "largest deviation %.3g m (Len LSB %.3g m)\n",
      s.model().nodes.size(), s.state().free_count, static_cast<long long>(worst_node), s.model().wrap.size(),
      worst_skin, s.metres(1));
  EXPECT_LE(worst_node, 2);
  std::printf("barnet arm: bind pose: worst wrapped vertex at %.3f of its derived bound\n", worst_ratio);
  EXPECT_LE(worst_ratio, 1.0);
}

TEST(BarnetArm, BulgeGrowsWithFlexionAndVolumeIsRestored) {
  ArmSession s;
  ASSERT_TRUE(s.ok()) << s.error();
  const int elbow = s.input("elbow.0");
  ASSERT_GE(elbow, 0);
  ASSERT_TRUE(s.step());
  const double rest_volume = segment_volume(s, [&s](uint32_t w) { return rest(s, w); });
  // The loaded ring's inner node (+y side) in model order.
  uint32_t inner = 0;
  for (const bn::LoadRecord& l : s.model().loads)
    if (s.model().nodes[l.node].rest.y > s.model().nodes[inner].rest.y || inner == 0) inner = l.node;
  double previous_bulge = -1;
  for (int deg = 0; deg <= 150; deg += 30) {
    s.inputs()[static_cast<size_t>(elbow)] = degrees_to_angle(deg);
    ASSERT_TRUE(s.step());
    const double bulge = s.metres(s.outputs().node[1][inner]) - s.metres(s.state().skinned[1][inner]);
    const double v_net = segment_volume(s, [&s](uint32_t w) { return wrapped(s, w); }) / rest_volume;
    const double v_lbs = segment_volume(s, [&s](uint32_t w) { return skinned(s, w); }) / rest_volume;
    std::printf(
        "barnet arm: elbow %3d deg: inner bulge %.2f mm, elbow segment volume / rest: skinning %.4f, "
        "bar-net %.4f; largest net displacement %.2f mm\n",
        deg, bulge * 1e3, v_lbs, v_net, s.metres(s.state().stats.max_displacement) * 1e3);
    EXPECT_GT(bulge, previous_bulge) << "bulge must grow with flexion";
    previous_bulge = bulge;
    if (deg >= 90) EXPECT_GT(v_net, v_lbs) << "the net restores volume smooth skinning loses";
  }
  // Positive beyond one Len LSB (the solve's error, ldlt_skyline.hpp).
  EXPECT_GT(previous_bulge, s.metres(1));
}

TEST(BarnetArm, ZeroAllocationsAcrossThousandsOfSteps) {
  ArmSession s;
  ASSERT_TRUE(s.ok()) << s.error();
  const int steps = sinew::test::soak_enabled() ? 100000 : 2000;
  const size_t elbow = static_cast<size_t>(s.input("elbow.0")), shoulder = static_cast<size_t>(s.input("shoulder.0"));
  sinew::test::AllocationCounter allocations;
  for (int i = 0; i < steps; ++i) {
    s.inputs()[elbow] = degrees_to_angle((i * 7) % 160);
    s.inputs()[shoulder] = degrees_to_angle((i * 3) % 90 - 45);
    ASSERT_TRUE(s.step());
  }
  std::printf("barnet arm: %d steps, %llu heap allocations, %u saturated values in the last step\n", steps,
              static_cast<unsigned long long>(allocations.allocations()), s.state().stats.saturated);
  EXPECT_EQ(allocations.allocations(), 0u);
  EXPECT_EQ(s.state().stats.saturated, 0u);
}
