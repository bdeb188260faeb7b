// Zero heap allocations across thousands of steps (engine + metaballs), with
// every stage on: jiggle, bulge, joint balls, smoothing and overlap.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "arm_scene.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/soak.hpp"

TEST(MetaballsAllocation, ZeroAllocationsAcrossThousandsOfSteps) {
  sinew::metaballs_build::Options o = sinew::test::arm_options();
  o.jiggle.push_back({"shoulder", 0.3, 0.7, 0.1});
  o.bulge.push_back({"shoulder", 0.3, 0.7, "shoulder", "elbow", 0.3});
  sinew::test::ArmScene s(sinew::rigc::SkinChoice::kDualQuaternion, o);
  ASSERT_TRUE(s.ok()) << s.error();
  const int steps = sinew::test::soak_enabled() ? 100000 : 2000;
  sinew::test::AllocationCounter allocations;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) {
    const double phase =
        (i % 400) / 400.0; // a triangle wave through bend and twist
    const double tri = phase < 0.5 ? 2 * phase : 2 - 2 * phase;
    ASSERT_TRUE(s.pose(60 * tri, 150 * tri, 180 * tri - 90));
  }
  const double ms = std::chrono::duration<double, std::milli>(
                        std::chrono::steady_clock::now() - t0)
                        .count();
  std::printf("metaballs: %d steps (engine + metaballs, %u vertices, %u "
              "balls): %llu heap allocations, %.3f ms/step "
              "(this build)\n",
              steps, s.rig().vertex_count(), s.model().ball_count(),
              static_cast<unsigned long long>(allocations.allocations()),
              ms / steps);
  EXPECT_EQ(allocations.allocations(), 0u);
  EXPECT_EQ(s.state().stats.steps, static_cast<uint64_t>(steps));
}
