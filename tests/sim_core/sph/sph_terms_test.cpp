// Each force term of the particle dynamics (sph-elastic-joints-tresca §4.1
// with Mueller 2003: pressure, viscosity, colour-field surface tension, and
// the elastic pull that restores the ideal distance, docs/sph.md) switched
// off on its own changes the result,
// and the measured-joint rule of docs/sph.md: a measured angle is not bent
// a second time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "sph_fixture.hpp"

using sinew::test::SphArm;

namespace {

namespace sph = sinew::sph;

struct TermsRun {
  std::vector<int32_t> words;  // every particle position after the run
  double loaded_bend = 0, released_bend = 0;
  int64_t peak_compression = 0;  // largest rho - rho0 seen while loaded, Q8.24
  double spread = 0;             // mean squared distance of the particles from their centroid, m^2
};

// 500 particles, 5 N toward +y on the wrist for 60 ticks, then 30 ticks
// released (the figure 3 load, short).
TermsRun run_terms(const sinew::layers::SphBuildOptions& o) {
  TermsRun r;
  SphArm arm(o);
  EXPECT_TRUE(arm.ok()) << arm.error();
  if (!arm.ok()) return r;
  for (int t = 0; t < 60; ++t) {
    EXPECT_TRUE(arm.tick(0, 5, 0).ok());
    for (uint32_t i = 0; i < arm.model().particle_count(); ++i)
      r.peak_compression = std::max<int64_t>(r.peak_compression, arm.state().pressure[i]);
  }
  r.loaded_bend = arm.bend_degrees();
  for (int t = 0; t < 30; ++t) EXPECT_TRUE(arm.tick(0, 0, 0).ok());
  r.released_bend = arm.bend_degrees();
  for (int c = 0; c < 3; ++c) {
    r.words.insert(r.words.end(), arm.state().position[c].begin(), arm.state().position[c].end());
    double mean = 0, square = 0;
    for (int32_t v : arm.state().position[c]) {
      mean += arm.metres(v);
      square += arm.metres(v) * arm.metres(v);
    }
    const double n = static_cast<double>(arm.state().position[c].size());
    r.spread += square / n - (mean / n) * (mean / n);
  }
  return r;
}

// Every term on, the surface tension too (sigma = 1 N/m; off by default,
// docs/sph.md).
sinew::layers::SphBuildOptions terms_options() {
  sinew::layers::SphBuildOptions o;
  o.particle_count = 500;
  o.surface_tension = 1.0;
  return o;
}

size_t words_changed(const TermsRun& a, const TermsRun& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.words.size() && i < b.words.size(); ++i) n += a.words[i] != b.words[i];
  return n;
}

}  // namespace

TEST(SphTerms, EachTermSwitchedOffChangesTheResult) {
  const TermsRun all = run_terms(terms_options());
  sinew::layers::SphBuildOptions o = terms_options();
  o.pressure_stiffness = 0;  // pressure_gain 0: the pressure term is off
  const TermsRun no_pressure = run_terms(o);
  o = terms_options();
  o.viscosity = 0;  // viscosity_gain 0
  const TermsRun no_viscosity = run_terms(o);
  o = terms_options();
  o.elastic_stiffness = 0;  // elastic_gain 0: no tension toward the ideal distance
  const TermsRun no_tension = run_terms(o);
  o = terms_options();
  o.surface_tension = 0;  // tension_gain 0: no colour-field surface tension
  const TermsRun no_surface = run_terms(o);
  std::printf(
      "terms: bend loaded / released (deg), peak rho - rho0\n"
      "  all          %7.2f %7.2f %8.3f\n  no pressure  %7.2f %7.2f %8.3f  (%zu words changed)\n"
      "  no viscosity %7.2f %7.2f %8.3f  (%zu words changed)\n  no tension   %7.2f %7.2f %8.3f  (%zu "
      "words changed)\n",
      all.loaded_bend, all.released_bend, static_cast<double>(all.peak_compression) / sph::kDensOne,
      no_pressure.loaded_bend, no_pressure.released_bend,
      static_cast<double>(no_pressure.peak_compression) / sph::kDensOne, words_changed(all, no_pressure),
      no_viscosity.loaded_bend, no_viscosity.released_bend,
      static_cast<double>(no_viscosity.peak_compression) / sph::kDensOne, words_changed(all, no_viscosity),
      no_tension.loaded_bend, no_tension.released_bend,
      static_cast<double>(no_tension.peak_compression) / sph::kDensOne, words_changed(all, no_tension));
  std::printf("  no surface   %7.2f %7.2f %8.3f  (%zu words changed); spread %.4g m^2 against %.4g with it\n",
              no_surface.loaded_bend, no_surface.released_bend,
              static_cast<double>(no_surface.peak_compression) / sph::kDensOne, words_changed(all, no_surface),
              no_surface.spread, all.spread);
  // A term that is computed but never reaches the particles leaves every word unchanged.
  EXPECT_GT(words_changed(all, no_pressure), 0u);
  EXPECT_GT(words_changed(all, no_viscosity), 0u);
  EXPECT_GT(words_changed(all, no_tension), 0u);
  EXPECT_GT(words_changed(all, no_surface), 0u);
  // Surface tension pulls every surface particle inward (sigma kappa > 0
  // on a convex body): with it the tissue is drawn together.
  EXPECT_LT(all.spread, no_surface.spread);
  // Pressure is what resists compression (p = k_p (rho - rho0), Mueller
  // 2003): without it the tissue in the crease gets denser.
  EXPECT_GT(no_pressure.peak_compression, all.peak_compression);
  // The tension toward the ideal distance is the elasticity of §5 / figure
  // 3 (d): without it nothing brings the released elbow back, so it stays
  // bent further than with it.
  // Surface tension has no rest shape either (a droplet has no preferred
  // orientation): it does not replace the elastic pull.
  EXPECT_GT(std::abs(no_tension.released_bend), std::abs(all.released_bend));
}

// The pull alone against its closed form, and what the pressure adds. The
// load acts as the distal bone's rigid-body angular acceleration at each
// distal particle's rest offset on the bone as it stands (flexed by the
// bend theta). With the pressure, viscosity and surface tension off each
// particle is then an independent damped oscillator with the equilibrium
// k_e (g - x) + beta n x R(theta) (g - c) = 0; in the plane of the bend, as
// complex numbers about the axis, x = g (1 + i k e^(i theta)) with
// k = beta / k_e = tau / (k_e I) (elastic_static_bend), and the best-fit
// rotation sph_step measures is arg(1 + i k e^(i theta)) = theta exactly
// when sin(theta) = k. So the pull alone holds a load up to k = 1 at
// theta = asin(k) and none beyond (its capacity, the wrist force whose tau
// is k_e I). At k = 0.8, ramped over 300 ticks and held 300 (the transient
// decays as exp(-c t / 2), below 10^-4 after them), the bend must meet
// asin(0.8) within the fixed-point rounding of the sums (0.05 degrees: the
// inertia and the torque are rounded to Q12 of a rig unit). At k = 1.3 it
// has no equilibrium and must run past 90 degrees. The tissue contracts
// toward the axis by sqrt(1 - k^2) at the equilibrium, so the pressure
// pushes back: with it the elbow bends less (printed).
TEST(SphTerms, PullAloneMeetsItsClosedForm) {
  double held[2] = {0, 0}, beyond = 0, oracle = 0, force = 0;
  for (int pressure = 0; pressure < 2; ++pressure) {
    sinew::layers::SphBuildOptions o;
    o.particle_count = 500;
    if (pressure == 0) o.pressure_stiffness = o.viscosity = 0;
    SphArm arm(o);
    ASSERT_TRUE(arm.ok()) << arm.error();
    force = 0.8 / sinew::test::elastic_static_bend(arm, 1.0, o);
    oracle = std::asin(sinew::test::elastic_static_bend(arm, force, o)) * 57.29577951308232;
    for (int t = 0; t < 600; ++t) ASSERT_TRUE(arm.tick(0, force * std::min(t + 1, 300) / 300.0, 0, false).ok());
    held[pressure] = arm.bend_degrees();
    if (pressure != 0) continue;
    SphArm over(o);
    ASSERT_TRUE(over.ok()) << over.error();
    for (int t = 0; t < 600 && beyond <= 90; ++t) {
      ASSERT_TRUE(over.tick(0, force / 0.8 * 1.3 * std::min(t + 1, 300) / 300.0, 0, false).ok());
      beyond = std::max(beyond, over.bend_degrees());
    }
  }
  std::printf(
      "pull: %.2f N at the wrist (k = 0.8): the pull alone holds %.3f deg (closed form asin(k) %.3f), with the "
      "pressure %.3f deg; at k = 1.3 the pull alone reaches %.1f deg\n",
      force, held[0], oracle, held[1], beyond);
  EXPECT_NEAR(held[0], oracle, 0.05) << "the pull alone must meet its closed form";
  EXPECT_GT(beyond, 90.0) << "beyond its capacity the pull alone has no equilibrium";
  EXPECT_LT(held[1], held[0]) << "the contracted tissue's pressure must push back";
}

TEST(SphMeasuredJoint, TheMeasuredAngleIsNotBentTwice) {
  // A wearable measures the elbow while a force acts on the wrist: the
  // measurement already contains the flexion the force causes. The joint
  // angle that reaches the skin is the measured one plus sph bend: with
  // joint_measured the bend must be exactly 0, the flexed distal frame the
  // measured one. The force still acts on the tissue (the particles of the
  // distal side take their share, which the elastic pull holds): the soft
  // tissue gives under the load while the bone keeps the measured angle.
  SphArm loaded(terms_options()), unloaded(terms_options()), simulated(terms_options());
  ASSERT_TRUE(loaded.ok() && unloaded.ok() && simulated.ok()) << loaded.error();
  const int elbow = loaded.input("elbow.0");
  ASSERT_GE(elbow, 0);
  for (int t = 0; t < 80; ++t) {
    // Measured elbow: ramps to 40 degrees (as the sensor would report under the load).
    const int32_t angle = static_cast<int32_t>(static_cast<int64_t>(std::min(t, 40)) * (int64_t{1} << 32) / 360);
    for (SphArm* arm : {&loaded, &unloaded, &simulated}) {
      arm->inputs()[static_cast<size_t>(elbow)] = angle;
      sinew::engine::engine_step(&arm->engine(), arm->inputs());
    }
    sph::SphInputs in;
    in.transforms = loaded.engine().model;
    in.force = {0, SphArm::newtons(10), 0};
    in.joint_measured = true;
    ASSERT_TRUE(sph::sph_step(&loaded.state(), in).ok());
    in.transforms = simulated.engine().model;
    in.joint_measured = false;
    ASSERT_TRUE(sph::sph_step(&simulated.state(), in).ok());
    in.transforms = unloaded.engine().model;
    in.force = {0, 0, 0};
    in.joint_measured = true;
    ASSERT_TRUE(sph::sph_step(&unloaded.state(), in).ok());
    ASSERT_EQ(loaded.state().bend, 0u) << "tick " << t;
    const sinew::fx::Mat34& distal = loaded.engine().model[loaded.model().joint.distal_joint];
    ASSERT_EQ(0, std::memcmp(&loaded.state().distal_flexed, &distal, sizeof distal)) << "tick " << t;
  }
  // The load toward +y moves the distal tissue toward +y (on average over
  // its particles, against the same run without the load), and leaves the
  // proximal tissue's particles where only the pressure of their
  // neighbours moves them.
  double distal_shift = 0, proximal_shift = 0;
  uint32_t distal = 0, proximal = 0;
  for (uint32_t i = 0; i < loaded.model().particle_count(); ++i) {
    const double dy = loaded.metres(loaded.state().position[1][i]) - unloaded.metres(unloaded.state().position[1][i]);
    if (loaded.model().bone[i] == static_cast<uint8_t>(sph::Bone::kDistal)) {
      distal_shift += dy;
      ++distal;
    } else {
      proximal_shift += dy;
      ++proximal;
    }
  }
  distal_shift /= distal;
  proximal_shift /= proximal;
  std::printf("measured joint: the load moves the distal tissue %.3f mm toward it, the proximal %.3f mm\n",
              distal_shift * 1e3, proximal_shift * 1e3);
  EXPECT_GT(distal_shift, 0.0) << "the force must act on a measured joint's tissue";
  EXPECT_GT(distal_shift, std::abs(proximal_shift));
  // The tissue still follows the measured motion on its own: the skin
  // near the joint takes the particles' offsets (eq. (2)).
  int64_t largest = 0;
  for (int c = 0; c < 3; ++c)
    for (int32_t v : loaded.state().skin_offset[c]) largest = std::max<int64_t>(largest, std::abs(int64_t{v}));
  EXPECT_GT(largest, 0);
  // Without the rule, the same force would bend the joint on top of the measurement.
  std::printf("measured joint: bend 0; the same force on a simulated joint adds %.2f deg\n", simulated.bend_degrees());
  EXPECT_GT(simulated.bend_degrees(), 0.0);
}
