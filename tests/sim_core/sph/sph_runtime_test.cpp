// Zero allocation across thousands of steps, stability under random joint
// motion and forces, and the skin coupling of eq. (2).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "host_tools/determinism/split_mix.hpp"
#include "sph_fixture.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/soak.hpp"

using sinew::test::SphArm;

namespace {
int64_t fx_clamp(int64_t v, int64_t m) { return v < -m ? -m : (v > m ? m : v); }
sinew::layers::SphBuildOptions small(uint32_t particles = 500) {
  sinew::layers::SphBuildOptions o;
  o.particle_count = particles;
  return o;
}
}  // namespace

namespace {

// Allocation does not depend on the particle count: the short form keeps
// 2000 steps on a small tissue; SINEW_SOAK=1 runs 10000 on 500 particles.
void expect_no_allocation(double surface_tension) {
  const uint32_t particles = sinew::test::soak_enabled() ? 500 : 64;
  const int steps = sinew::test::soak_enabled() ? 10000 : 2000;
  sinew::layers::SphBuildOptions o = small(particles);
  o.surface_tension = surface_tension;
  SphArm arm(o);
  ASSERT_TRUE(arm.ok()) << arm.error();
  const size_t elbow = static_cast<size_t>(arm.input("elbow.0"));
  sinew::test::AllocationCounter counter;
  for (int t = 0; t < steps; ++t) {
    arm.inputs()[elbow] = (t % 400) * 200000;
    ASSERT_TRUE(arm.tick(0, (t / 500) % 2 ? 10 : 0, 0).ok());
    sinew::sph::sph_apply_skin(arm.state(), arm.engine().vertices.position);
  }
  std::printf("sph: %llu heap allocations in %d engine + sph steps (%u particles, surface tension %g N/m)\n",
              static_cast<unsigned long long>(counter.allocations()), steps, particles, surface_tension);
  EXPECT_EQ(counter.allocations(), 0u);
}

}  // namespace

TEST(SphRuntime, StepsNeverAllocate) { expect_no_allocation(0); }

// The colour-field sums are carved at init only when the tension is on
// (sph_state_bytes): that path allocates nothing either.
TEST(SphRuntime, StepsWithSurfaceTensionNeverAllocate) {
  SphArm probe(small(64));
  sinew::layers::SphBuildOptions o = small(64);
  o.surface_tension = 1.0;
  SphArm tension(o);
  ASSERT_TRUE(probe.ok() && tension.ok());
  ASSERT_NE(tension.model().params.tension_gain, 0) << "the tension path must run";
  ASSERT_GT(sinew::sph::sph_state_bytes(tension.model()), sinew::sph::sph_state_bytes(probe.model()));
  expect_no_allocation(1.0);
}

TEST(SphRuntime, RandomMotionAndForcesStayBounded) {
  const int steps = sinew::test::soak_enabled() ? 100000 : 600;
  SphArm arm(small());
  ASSERT_TRUE(arm.ok()) << arm.error();
  sinew::determinism::SplitMix64 rng(42);
  const int64_t bound = 2 * int64_t{arm.model().params.grid_radius};
  int64_t worst = 0;
  double fx = 0, fy = 0, fz = 0;
  std::vector<int32_t> target(arm.inputs().size(), 0);
  for (int t = 0; t < steps; ++t) {
    // Random joint targets, approached at most ~0.1 degree per tick (100
    // deg/s).
    for (size_t i = 0; i < target.size(); ++i) {
      const int64_t d = fx_clamp(int64_t{target[i]} - arm.inputs()[i], 1200000);
      arm.inputs()[i] = static_cast<int32_t>(arm.inputs()[i] + d);
    }
    if (t % 50 == 0) {
      for (size_t i = 0; i < target.size(); ++i) target[i] = rng.range(-(1 << 29), 1 << 29);
      fx = rng.range(-20, 20);
      fy = rng.range(-20, 20);
      fz = rng.range(-20, 20);
    }
    ASSERT_TRUE(arm.tick(fx, fy, fz, (t / 5000) % 2 == 0).ok());
    const auto& m = arm.engine().model[arm.model().joint.distal_joint];
    for (uint32_t i = 0; i < arm.model().particle_count(); ++i)
      for (int a = 0; a < 3; ++a) {
        const int64_t d = std::abs(int64_t{arm.state().position[a][i]} - m.t[a]);
        worst = std::max(worst, d);
      }
    ASSERT_LT(worst, bound) << "particle escaped at step " << t;
  }
  std::printf(
      "sph stability: %d steps of random motion and forces, largest "
      "particle offset from the joint %.4f m "
      "(bound %.4f m), yielded particles %u\n",
      steps, arm.metres(static_cast<int32_t>(worst)), arm.metres(static_cast<int32_t>(bound)),
      arm.state().yielded_particles);
}

TEST(SphRuntime, SkinNearTheJointTakesTheParticleDisplacement) {
  SphArm arm(small());
  ASSERT_TRUE(arm.ok()) << arm.error();
  for (int t = 0; t < 200; ++t) ASSERT_TRUE(arm.tick(0, 15, 0).ok());
  int64_t largest = 0;
  for (uint32_t v = 0; v < arm.model().skin_count(); ++v)
    for (int a = 0; a < 3; ++a) largest = std::max<int64_t>(largest, std::abs(int64_t{arm.state().skin_offset[a][v]}));
  std::printf(
      "sph skin: %u vertices near the elbow, largest eq. (2) "
      "displacement %.3f mm at bend %.2f deg\n",
      arm.model().skin_count(), arm.metres(static_cast<int32_t>(largest)) * 1e3, arm.bend_degrees());
  EXPECT_GT(arm.model().skin_count(), 100u);
  EXPECT_GT(largest, 0);
  // Eq. (2) in double: A(r) = sum_j A_j W_j / rho_j with A_j the particle's
  // offset from its anchor (the flexed distal frame or its ideal position)
  // and the rest kernel weights. The runtime rounds each weight W_j / rho_j
  // to Q2.30 (0.5 x 2^-30, times |A_j|) and each term to Len (0.5 LSB).
  const sinew::sph::SphState& st = arm.state();
  const sinew::sph::SphModel& m = arm.model();
  std::vector<double> offset[3];
  for (uint32_t i = 0; i < m.particle_count(); ++i) {
    const sinew::fx::Vec3 r{m.rest_local[0][i], m.rest_local[1][i], m.rest_local[2][i]};
    const sinew::fx::Vec3 anchor = m.bone[i] == static_cast<uint8_t>(sinew::sph::Bone::kDistal)
                                       ? sinew::fx::transform_point(st.distal_flexed, r)
                                       : sinew::fx::Vec3{st.ideal[0][i], st.ideal[1][i], st.ideal[2][i]};
    offset[0].push_back(static_cast<double>(st.position[0][i]) - anchor.x);
    offset[1].push_back(static_cast<double>(st.position[1][i]) - anchor.y);
    offset[2].push_back(static_cast<double>(st.position[2][i]) - anchor.z);
  }
  for (uint32_t v = 0; v < m.skin_count(); ++v) {
    double want[3] = {0, 0, 0}, bound[3] = {0, 0, 0};
    for (uint32_t k = 0; k < st.skin_count[v]; ++k) {
      const size_t at = size_t{v} * sinew::sph::kMaxVertexNeighbours + k;
      const uint32_t j = st.skin_particle[at];
      const double w = static_cast<double>(st.skin_weight[at]) * static_cast<double>(st.inv_density[j]) / 0x1p60;
      for (int a = 0; a < 3; ++a) {
        want[a] += offset[a][j] * w;
        bound[a] += 0.5 + std::abs(offset[a][j]) * 0.5 / 0x1p30;
      }
    }
    for (int a = 0; a < 3; ++a)
      ASSERT_LE(std::abs(st.skin_offset[a][v] - want[a]), bound[a] + 1e-9) << "vertex " << v << " axis " << a;
  }
}

// A scalar force sensor's reading becomes a force perpendicular to the
// flexion axis and the lever arm, of the same magnitude; positive flexes.
TEST(SphRuntime, FlexionForceIsPerpendicularAndFlexes) {
  SphArm arm(small(256));
  ASSERT_TRUE(arm.ok()) << arm.error();
  const size_t elbow = static_cast<size_t>(arm.input("elbow.0"));
  arm.inputs()[elbow] = 1 << 28;  // 22.5 deg: the rule holds in any pose
  sinew::engine::engine_step(&arm.engine(), arm.inputs());
  const sinew::sph::SphModel& m = arm.model();
  sinew::fx::Vec3 f;
  ASSERT_TRUE(sinew::sph::sph_flexion_force(m, arm.engine().model, SphArm::newtons(20), &f));
  const double n[3] = {f.x / 65536.0, f.y / 65536.0, f.z / 65536.0};
  const double magnitude = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const sinew::fx::Mat34& distal = arm.engine().model[m.joint.distal_joint];
  const sinew::fx::Vec3 axis = sinew::fx::transform_vector(distal, m.joint.axis);
  const double along_axis = (n[0] * axis.x + n[1] * axis.y + n[2] * axis.z) / 1073741824.0;
  std::printf("20 N reading -> (%.4f, %.4f, %.4f) N, |F| %.5f N, along the axis %.6f N\n", n[0], n[1], n[2], magnitude,
              along_axis);
  EXPECT_NEAR(magnitude, 20.0, 1e-3);
  EXPECT_NEAR(along_axis, 0.0, 1e-3);

  // Held for 100 ticks, it bends the elbow forward; the opposite reading back.
  double bend[2] = {0, 0};
  for (int sign = 0; sign < 2; ++sign) {
    SphArm fresh(small(256));
    ASSERT_TRUE(fresh.ok());
    for (int t = 0; t < 100; ++t) {
      sinew::engine::engine_step(&fresh.engine(), fresh.inputs());
      sinew::sph::SphInputs in;
      in.transforms = fresh.engine().model;
      ASSERT_TRUE(sinew::sph::sph_flexion_force(fresh.model(), fresh.engine().model,
                                                SphArm::newtons(sign == 0 ? 10 : -10), &in.force));
      ASSERT_TRUE(sinew::sph::sph_step(&fresh.state(), in).ok());
    }
    bend[sign] = fresh.bend_degrees();
  }
  std::printf("bend after 100 ticks: +10 N %.2f deg, -10 N %.2f deg\n", bend[0], bend[1]);
  // The claim is the sign: a positive reading flexes, a negative extends.
  EXPECT_GT(bend[0], 0.0);
  EXPECT_LT(bend[1], 0.0);
}
