// The paper's experiments (sph-elastic-joints-tresca §5) on the built-in
// arm's elbow: figure 3 (flex under a side force, bounce back), figure 4
// (growing force with and without the Tresca yield) and table 1 (particle
// counts). Each prints the figures it measures.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "sph_fixture.hpp"
#include "tests/support/soak.hpp"

using sinew::test::elastic_static_bend;
using sinew::test::SphArm;

namespace {

sinew::layers::SphBuildOptions options(uint32_t particles) {
  sinew::layers::SphBuildOptions o;
  o.particle_count = particles;
  return o;
}

constexpr double kRadToDeg = 57.29577951308232;

}  // namespace

TEST(SphFigure3, SideForceFlexesTheElbowAndItSpringsBack) {
  SphArm arm(options(500));
  ASSERT_TRUE(arm.ok()) << arm.error();
  // Short form: 150 ticks loaded, 150 released; SINEW_SOAK=1: 200 + 300.
  const int loaded_ticks = sinew::test::soak_enabled() ? 200 : 150;
  const int released_ticks = sinew::test::soak_enabled() ? 300 : 150;
  double peak = 0;
  const double static_bend = elastic_static_bend(arm, 5.0, options(500));
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
  // Bounds from the tension alone (a damped oscillator, omega^2 = k_e,
  // velocity decay c; docs/sph.md "Gains"): a load switched on from rest
  // (a step) never deflects it beyond twice its static deflection, and
  // after release its amplitude decays at least as exp(-c t / 2) /
  // sqrt(1 - zeta^2), zeta = c / (2 omega); viscosity only damps more and
  // pressure only stiffens.
  const sinew::layers::SphBuildOptions o = options(500);
  const double zeta = o.damping / (2 * std::sqrt(o.elastic_stiffness));
  const double envelope = std::exp(-o.damping * released_ticks / o.tick_hz / 2) / std::sqrt(1 - zeta * zeta);
  std::printf("figure 3: static bend of the tension alone %.2f deg, decay envelope after release %.3f\n",
              static_bend * kRadToDeg, envelope);
  EXPECT_GT(loaded, 0.0) << "the force must flex the elbow toward it";
  EXPECT_LE(peak, 2 * static_bend * kRadToDeg) << "beyond the step response of the tension";
  EXPECT_LT(std::abs(after), 2 * static_bend * kRadToDeg * envelope) << "the elbow must spring back toward rest";
  EXPECT_FALSE(arm.state().joint_yielded);
}

TEST(SphFigure4, TrescaYieldStopsTheBendUnderAGrowingForce) {
  SphArm capacity_arm(options(500));
  ASSERT_TRUE(capacity_arm.ok()) << capacity_arm.error();
  double final_bend[2] = {0, 0}, max_bend[2] = {0, 0}, bend_at_yield = 0, force_at_yield = 0, static_bend_at_yield = 0;
  double released_bend = 0;
  uint32_t yielded[2] = {0, 0};
  int yield_entries = 0;
  bool yields_after_release = true;
  const int release = 300;
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
      if (arm.state().joint_yielded && !yielded_before && ++yield_entries == 1) {
        bend_at_yield = b;
        force_at_yield = f;
        static_bend_at_yield = elastic_static_bend(arm, f, options(500));
        std::printf("  joint yielded at tick %d, force %.1f N, bend %.2f deg\n", t + 1, f, b);
      }
      yielded_before = arm.state().joint_yielded;
      if (t % every == every - 1)
        std::printf("  F=%5.1f N  bend %6.2f deg  yielded particles %u\n", f, b, arm.state().yielded_particles);
    }
    final_bend[tresca] = arm.bend_degrees();
    yielded[tresca] = arm.state().yielded_particles;
    if (tresca == 0) continue;
    // The force released: the yield is not latched, the densities fall
    // back below the limit and the elbow springs back.
    for (int t = 0; t < release; ++t) ASSERT_TRUE(arm.tick(0, 0, 0, true).ok());
    released_bend = arm.bend_degrees();
    yields_after_release = arm.state().joint_yielded;
  }
  std::printf(
      "figure 4: final bend without yield %.2f deg (max %.2f), with "
      "yield %.2f deg (max %.2f, limit reached at %.2f), "
      "yielded particles %u / %u\n",
      final_bend[0], max_bend[0], final_bend[1], max_bend[1], bend_at_yield, yielded[0], yielded[1]);
  EXPECT_EQ(yielded[0], 0u);
  EXPECT_GT(yielded[1], 0u);
  // Figure 4 (c) against (d): without the yield condition the bend keeps
  // increasing. The ramp ends past the pull's capacity (the wrist force
  // whose torque is k_e I; SphTerms.PullAloneMeetsItsClosedForm), where
  // the pull alone has no equilibrium: the unyielded elbow runs past 90
  // degrees, the yielded one stops below it.
  const double capacity = 1 / elastic_static_bend(capacity_arm, 1.0, options(500));
  std::printf("figure 4: the pull's capacity %.2f N, under the ramp's 40 N\n", capacity);
  ASSERT_LT(capacity, 40.0);
  EXPECT_GT(max_bend[0], 90.0) << "without the yield condition the bend keeps increasing";
  EXPECT_LT(max_bend[1], 90.0) << "with it the bend stops";
  // With it the load torque stops growing while the joint yields (the
  // abstract: "the object is no longer subjected to force"), and the joint
  // leaves the yield only when no particle yields any more: under a
  // growing force it yields once and stays. The load is then
  // non-decreasing and bounded by its value at the yield, a sum of positive
  // steps, so the tension (a damped oscillator) never deflects beyond twice
  // its static deflection under that load.
  std::printf("figure 4: yield at %.1f N (%d entries), static bend of the tension alone there %.2f deg\n",
              force_at_yield, yield_entries, static_bend_at_yield * kRadToDeg);
  EXPECT_EQ(yield_entries, 1) << "under a growing force the joint yields once and holds";
  EXPECT_LE(max_bend[1], 2 * static_bend_at_yield * kRadToDeg) << "with it the bend stops at the limit";
  // Released, the tension's oscillator decays from at most max_bend at
  // least as exp(-c t / 2) / sqrt(1 - zeta^2) (figure 3's envelope).
  const sinew::layers::SphBuildOptions o = options(500);
  const double zeta = o.damping / (2 * std::sqrt(o.elastic_stiffness));
  const double envelope = std::exp(-o.damping * release / o.tick_hz / 2) / std::sqrt(1 - zeta * zeta);
  std::printf("figure 4: %d ticks after the release the bend is %.3f deg (envelope bound %.3f deg)\n", release,
              released_bend, max_bend[1] * envelope);
  EXPECT_FALSE(yields_after_release) << "the yield must not outlast the load";
  EXPECT_LT(std::abs(released_bend), max_bend[1] * envelope) << "released, the elbow must spring back";
}

TEST(SphTable1, ParticleCountsSideBySide) {
  // Table 1 reports "at what angle the elbow would stop" under the yield,
  // a static figure. The load is therefore ramped slowly against the
  // tension's oscillator (omega = sqrt(k_e) = 55 rad/s, period 115 ms,
  // c = 40 /s): 400 ticks (3.5 periods); SINEW_SOAK=1: 1000 (8.7). The
  // ramp's start transient decays as exp(-c t / 2), below 1 % after
  // 2 ln(100) / c = 230 ms: a yield before that would compare transients,
  // not stop angles, so it is checked.
  const int ramp = sinew::test::soak_enabled() ? 1000 : 400, hold = 50;
  const sinew::layers::SphBuildOptions reference = options(500);
  const double transient_ticks = 2 * std::log(100.0) / reference.damping * reference.tick_hz;
  std::printf(
      "table 1: same elbow, force ramp 0 -> 30 N over %d ticks then "
      "held %d ticks, Tresca on\n",
      ramp, hold);
  std::printf(
      "  particles  h(mm)  step(us)  pairs/tick  pairs/particle/substep  yield tick  yield force(N)  stop "
      "angle(deg)  final(deg)\n");
  const uint32_t counts[3] = {500u, 1000u, 1500u};
  double stop[3] = {0, 0, 0}, pairs[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    const sinew::layers::SphBuildOptions o = options(counts[k]);
    SphArm arm(o);
    ASSERT_TRUE(arm.ok()) << arm.error();
    double seconds = 0, yield_force = 0;
    int yield_tick = -1;
    for (int t = 0; t < ramp + hold; ++t) {
      const double f = t < ramp ? 30.0 * (t + 1) / ramp : 30.0;
      const auto start = std::chrono::steady_clock::now();
      ASSERT_TRUE(arm.tick(0, f, 0).ok());
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      stop[k] = std::max(stop[k], arm.bend_degrees());
      pairs[k] += static_cast<double>(arm.state().stats.neighbour_pairs);
      if (arm.state().joint_yielded && yield_tick < 0) {
        yield_tick = t + 1;
        yield_force = f;
      }
    }
    pairs[k] /= ramp + hold;
    std::printf("  %9u  %5.1f  %8.1f  %10.0f  %22.2f  %10d  %14.2f  %15.2f  %10.2f\n", counts[k],
                arm.built().h_metres * 1e3, seconds / (ramp + hold) * 1e6, pairs[k], pairs[k] / counts[k] / o.substeps,
                yield_tick, yield_force, stop[k], arm.bend_degrees());
    // The stop angle is the yield's (figure 4 (d)) once the ramp is quasi-static.
    ASSERT_GT(yield_tick, transient_ticks) << counts[k] << " particles: the joint must yield, after the transient";
    ASSERT_GT(stop[k], 0.0) << "the load flexes the elbow (figure 3 (c))";
    // Bounded work: the search keeps at most max_neighbours per particle
    // and substep (docs/sph.md, "Limits").
    EXPECT_LE(pairs[k], static_cast<double>(counts[k]) * o.max_neighbours * o.substeps);
  }
  // The paper's findings (§5, table 1). Stop angles:
  //  - "1500 particles were found to be subject to strong elasticity and
  //    bending restrictions owing to the high density of the particles",
  //    while with 500 "the density was not significant ... so the yield
  //    conditions ... were not properly applied": the elbow stops earlier
  //    with 1500 particles than with 500. (A finer kernel, h ~ N^(-1/3),
  //    resolves the density rise of the crease, which the yield reads.)
  EXPECT_LT(stop[2], stop[0]) << "1500 particles must stop the elbow before 500 do";
  //  - "1000 particles were measured with elasticity and yield conditions
  //    similar to those of 1500": 1000 stops nearer 1500 than 500 does.
  EXPECT_LT(std::abs(stop[1] - stop[2]), std::abs(stop[0] - stop[2]));
  // Cost ("500 ... very high speed", "1500 ... slow", 1000's "speed
  // increased significantly" against 1500), counted as neighbour pairs per
  // tick, the work of a step (deterministic; the times above are printed,
  // not asserted). With h a fixed number of spacings, every particle's
  // kernel holds the same number of lattice neighbours in the bulk and
  // fewer within h of the surface, a fraction ~ 3 A h / (16 V) of the
  // capsule that falls as N^(-1/3): the work grows at least in proportion
  // to N. So 1000 costs at most 2/3 of 1500, and 500 at most half of 1000.
  EXPECT_GE(pairs[1] / pairs[0], 1000.0 / 500.0);
  EXPECT_GE(pairs[2] / pairs[1], 1500.0 / 1000.0);
}
