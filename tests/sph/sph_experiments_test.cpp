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

using sinew::test::SphArm;

namespace {

sinew::layers::SphBuildOptions options(uint32_t particles) {
  sinew::layers::SphBuildOptions o;
  o.particle_count = particles;
  return o;
}

// Static bend (radians) of the distal tissue held by the elastic tension
// alone under `fy_newtons` toward +y at the load point, at the rest pose:
// each distal particle (mass m) takes the load as the rigid-body
// acceleration tau r / (m I_sum) and the pull -k_e theta r, so they balance
// at theta = tau / (k_e sum m r_perp^2) (docs/sph.md, "Gains"). Pressure
// only adds stiffness against the crease's compression.
double elastic_static_bend(SphArm& arm, double fy_newtons, const sinew::layers::SphBuildOptions& o) {
  const sinew::sph::SphModel& m = arm.model();
  const sinew::fx::Mat34& d = arm.engine().model[m.joint.distal_joint];
  const double lin = 1.0 / 16777216.0;
  double axis[3], load[3], centre[3];
  const sinew::fx::Vec3 a = m.joint.axis, lp = m.joint.load_point;
  const double al[3] = {a.x / 1073741824.0, a.y / 1073741824.0, a.z / 1073741824.0};
  const double ll[3] = {arm.metres(lp.x), arm.metres(lp.y), arm.metres(lp.z)};
  for (int r = 0; r < 3; ++r) {
    axis[r] = (d.m[r][0] * al[0] + d.m[r][1] * al[1] + d.m[r][2] * al[2]) * lin;
    load[r] = (d.m[r][0] * ll[0] + d.m[r][1] * ll[1] + d.m[r][2] * ll[2]) * lin;
    centre[r] = arm.metres(d.t[r]);
  }
  const double norm = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  for (double& v : axis) v /= norm;
  // tau = (r x F) . n with F = (0, fy, 0): (r_z * 0 - ...) = -r_z fy n_x + r_x fy n_z.
  const double tau = fy_newtons * (load[0] * axis[2] - load[2] * axis[0]);
  const double mass = o.tissue_mass / m.particle_count();
  double inertia = 0;
  for (uint32_t i = 0; i < m.particle_count(); ++i) {
    if (m.bone[i] != static_cast<uint8_t>(sinew::sph::Bone::kDistal)) continue;
    double r[3] = {arm.metres(m.rest_model[0][i]) - centre[0], arm.metres(m.rest_model[1][i]) - centre[1],
                   arm.metres(m.rest_model[2][i]) - centre[2]};
    const double along = r[0] * axis[0] + r[1] * axis[1] + r[2] * axis[2];
    for (int c = 0; c < 3; ++c) r[c] -= along * axis[c];
    inertia += mass * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  }
  return tau / (o.elastic_stiffness * inertia);
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
  double final_bend[2] = {0, 0}, max_bend[2] = {0, 0}, bend_at_yield = 0, force_at_yield = 0, static_bend_at_yield = 0;
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
  }
  std::printf(
      "figure 4: final bend without yield %.2f deg (max %.2f), with "
      "yield %.2f deg (max %.2f, limit reached at %.2f), "
      "yielded particles %u / %u\n",
      final_bend[0], max_bend[0], final_bend[1], max_bend[1], bend_at_yield, yielded[0], yielded[1]);
  EXPECT_EQ(yielded[0], 0u);
  EXPECT_GT(yielded[1], 0u);
  // Figure 4 (c) against (d): without the yield condition the elbow ends
  // bent further than it ever gets with it.
  EXPECT_GT(final_bend[0], max_bend[1]) << "without the yield condition the bend keeps increasing";
  // With it the load torque stops growing at the yield (capped, §4.2): the
  // load is then non-decreasing and bounded by its value at the yield, a sum
  // of positive steps, so the tension (a damped oscillator) never deflects
  // beyond twice its static deflection under that load.
  std::printf("figure 4: yield at %.1f N, static bend of the tension alone there %.2f deg\n", force_at_yield,
              static_bend_at_yield * kRadToDeg);
  EXPECT_LE(max_bend[1], 2 * static_bend_at_yield * kRadToDeg) << "with it the bend stops at the limit";
}

TEST(SphTable1, ParticleCountsSideBySide) {
  // Short form: 150 ticks of ramp + 25 held; SINEW_SOAK=1: 300 + 50.
  const int ramp = sinew::test::soak_enabled() ? 300 : 150, hold = sinew::test::soak_enabled() ? 50 : 25;
  std::printf(
      "table 1: same elbow, force ramp 0 -> 30 N over %d ticks then "
      "held %d ticks, Tresca on\n",
      ramp, hold);
  std::printf(
      "  particles  h(mm)  step(us)  steps/s  pairs/tick  final bend(deg)  max "
      "bend(deg)  yielded  joint yielded\n");
  const uint32_t counts[3] = {500u, 1000u, 1500u};
  double max_bend[3] = {0, 0, 0}, final_bend[3] = {0, 0, 0}, pairs[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    SphArm arm(options(counts[k]));
    ASSERT_TRUE(arm.ok()) << arm.error();
    double seconds = 0;
    for (int t = 0; t < ramp + hold; ++t) {
      const double f = t < ramp ? 30.0 * (t + 1) / ramp : 30.0;
      const auto start = std::chrono::steady_clock::now();
      ASSERT_TRUE(arm.tick(0, f, 0).ok());
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      max_bend[k] = std::max(max_bend[k], arm.bend_degrees());
      pairs[k] += static_cast<double>(arm.state().stats.neighbour_pairs);
    }
    pairs[k] /= ramp + hold;
    final_bend[k] = arm.bend_degrees();
    std::printf("  %9u  %5.1f  %8.1f  %7.0f  %10.0f  %15.2f  %13.2f  %7u  %s\n", counts[k], arm.built().h_metres * 1e3,
                seconds / (ramp + hold) * 1e6, (ramp + hold) / seconds, pairs[k], arm.bend_degrees(), max_bend[k],
                arm.state().yielded_particles, arm.state().joint_yielded ? "yes" : "no");
  }
  // The paper's findings (§5, table 1), as trends, not numbers. The angle
  // compared is where the elbow stops under the held load (the table's
  // "bend angle"; the peak is the dynamic overshoot of the ramp).
  //  - the load flexes the elbow at every count (figure 3 (c));
  for (double b : final_bend) EXPECT_GT(b, 0.0);
  //  - "1000 particles were measured with elasticity and yield conditions
  //    similar to those of 1500": 1000 stops nearer 1500 than 500 does.
  //    (The paper's other bend finding, 1500 bending less than 500, is
  //    printed, not asserted: docs/sph.md, "Table 1", says why.)
  EXPECT_LT(std::abs(final_bend[1] - final_bend[2]), std::abs(final_bend[0] - final_bend[2]));
  //  - cost grows with the count ("500 ... very high speed", "1500 ...
  //    slow", 1000 "speed increased significantly" against 1500). Measured
  //    as neighbour pairs evaluated per tick, the work of a step
  //    (deterministic; times are printed above, not asserted).
  EXPECT_LT(pairs[0], pairs[1]);
  EXPECT_LT(pairs[1], pairs[2]);
}
