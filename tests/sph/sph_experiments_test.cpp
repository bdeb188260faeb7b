// The paper's experiments (sph-elastic-joints-tresca §5) on the built-in
// arm's elbow: figure 3 (flex under a side force, bounce back), figure 4
// (growing force with and without the Tresca yield) and table 1 (particle
// counts). Each prints the figures it measures.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "sph_fixture.hpp"
#include "tests/support/soak.hpp"

using sinew::test::SphArm;

namespace {

sinew::layers::SphBuildOptions options(uint32_t particles) {
  sinew::layers::SphBuildOptions o;
  o.particle_count = particles;
  return o;
}

}  // namespace

TEST(SphFigure3, SideForceFlexesTheElbowAndItSpringsBack) {
  SphArm arm(options(500));
  ASSERT_TRUE(arm.ok()) << arm.error();
  // Short form: 150 ticks loaded, 150 released; SINEW_SOAK=1: 200 + 300.
  const int loaded_ticks = sinew::test::soak_enabled() ? 200 : 150;
  const int released_ticks = sinew::test::soak_enabled() ? 300 : 150;
  double peak = 0;
  std::printf(
      "figure 3: 5 N on the wrist toward +y for %d ticks (1 kHz), then "
      "released\n  tick  bend(deg)\n",
      loaded_ticks);
  for (int t = 0; t < loaded_ticks; ++t) {
    ASSERT_TRUE(arm.tick(0, 5, 0).ok());
    peak = std::max(peak, arm.bend_degrees());
    if (t % 25 == 24) std::printf("  %4d  %7.2f\n", t + 1, arm.bend_degrees());
  }
  const double loaded = arm.bend_degrees();
  double after = 0;
  for (int t = loaded_ticks; t < loaded_ticks + released_ticks; ++t) {
    ASSERT_TRUE(arm.tick(0, 0, 0).ok());
    after = arm.bend_degrees();
    if (t % 25 == 24) std::printf("  %4d  %7.2f (released)\n", t + 1, after);
  }
  std::printf(
      "figure 3: peak %.2f deg, loaded %.2f deg, %d ticks after "
      "release %.3f deg\n",
      peak, loaded, released_ticks, after);
  EXPECT_GT(loaded, 5.0) << "the force must flex the elbow";
  EXPECT_LT(std::abs(after), 0.1 * loaded) << "the elbow must spring back toward rest";
  EXPECT_FALSE(arm.state().joint_yielded);
}

TEST(SphFigure4, TrescaYieldStopsTheBendUnderAGrowingForce) {
  double final_bend[2] = {0, 0}, max_bend[2] = {0, 0}, bend_at_yield = 0;
  uint32_t yielded[2] = {0, 0};
  // A faster ramp overshoots dynamically past the yield bend, so both forms
  // keep the 400-tick ramp (about 7 s for both curves under the sanitizers).
  const int ramp = 400;
  const int every = ramp / 8;
  for (int tresca = 0; tresca < 2; ++tresca) {
    SphArm arm(options(500));
    ASSERT_TRUE(arm.ok()) << arm.error();
    std::printf("figure 4 (%s yield): force ramp 0 -> 40 N over %d ticks\n", tresca ? "with" : "without", ramp);
    bool yielded_before = false;
    for (int t = 0; t < ramp; ++t) {
      const double f = 40.0 * (t + 1) / ramp;
      ASSERT_TRUE(arm.tick(0, f, 0, tresca != 0).ok());
      const double b = arm.bend_degrees();
      max_bend[tresca] = std::max(max_bend[tresca], b);
      if (arm.state().joint_yielded && !yielded_before) {
        bend_at_yield = b;
        std::printf("  joint yielded at tick %d, force %.1f N, bend %.2f deg\n", t + 1, f, b);
      }
      yielded_before = arm.state().joint_yielded;
      if (t % every == every - 1)
        std::printf("  F=%5.1f N  bend %6.2f deg  yielded particles %u\n", f, b, arm.state().yielded_particles);
    }
    final_bend[tresca] = arm.bend_degrees();
    yielded[tresca] = arm.state().yielded_particles;
  }
  std::printf(
      "figure 4: final bend without yield %.2f deg (max %.2f), with "
      "yield %.2f deg (max %.2f, limit reached at %.2f), "
      "yielded particles %u / %u\n",
      final_bend[0], max_bend[0], final_bend[1], max_bend[1], bend_at_yield, yielded[0], yielded[1]);
  EXPECT_EQ(yielded[0], 0u);
  EXPECT_GT(yielded[1], 0u);
  EXPECT_GT(final_bend[0], 55.0) << "without the yield condition the bend keeps increasing";
  EXPECT_LT(max_bend[1], bend_at_yield + 3.0) << "with it the bend stops at the limit";
  EXPECT_LT(max_bend[1], max_bend[0] - 8.0);
}

TEST(SphTable1, ParticleCountsSideBySide) {
  // Short form: 150 ticks of ramp + 25 held; SINEW_SOAK=1: 300 + 50.
  const int ramp = sinew::test::soak_enabled() ? 300 : 150, hold = sinew::test::soak_enabled() ? 50 : 25;
  std::printf(
      "table 1: same elbow, force ramp 0 -> 30 N over %d ticks then "
      "held %d ticks, Tresca on\n",
      ramp, hold);
  std::printf(
      "  particles  h(mm)  step(us)  steps/s  final bend(deg)  max "
      "bend(deg)  yielded  joint yielded\n");
  for (uint32_t n : {500u, 1000u, 1500u}) {
    SphArm arm(options(n));
    ASSERT_TRUE(arm.ok()) << arm.error();
    double max_bend = 0, seconds = 0;
    for (int t = 0; t < ramp + hold; ++t) {
      const double f = t < ramp ? 30.0 * (t + 1) / ramp : 30.0;
      const auto start = std::chrono::steady_clock::now();
      ASSERT_TRUE(arm.tick(0, f, 0).ok());
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      max_bend = std::max(max_bend, arm.bend_degrees());
    }
    std::printf("  %9u  %5.1f  %8.1f  %7.0f  %15.2f  %13.2f  %7u  %s\n", n, arm.built().h_metres * 1e3,
                seconds / (ramp + hold) * 1e6, (ramp + hold) / seconds, arm.bend_degrees(), max_bend,
                arm.state().yielded_particles, arm.state().joint_yielded ? "yes" : "no");
    EXPECT_GT(max_bend, 10.0);
  }
}
