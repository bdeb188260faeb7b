// Zero heap allocations across thousands of metaballs steps, with every stage
// on: jiggle, bulge, joint balls, smoothing and overlap.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <vector>

#include "arm_scene.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/soak.hpp"

TEST(MetaballsAllocation, ZeroAllocationsAcrossThousandsOfSteps) {
  sinew::metaballs_build::Options o = sinew::test::arm_options();
  o.jiggle.push_back({"shoulder", 0.3, 0.7, 0.1});
  o.bulge.push_back({"shoulder", 0.3, 0.7, "shoulder", "elbow", 0.3});
  sinew::test::ArmScene s(sinew::rigc::SkinChoice::kDualQuaternion, o);
  ASSERT_TRUE(s.ok()) << s.error();
  // The engine's own test covers its allocations; here its joint transforms
  // for one period of a triangle wave through bend and twist are computed
  // first, and the metaballs step then replays them.
  constexpr int kPeriod = 400;
  std::vector<std::vector<sinew::fx::Mat34>> poses;
  for (int i = 0; i < kPeriod; ++i) {
    const double phase = static_cast<double>(i) / kPeriod;
    const double tri = phase < 0.5 ? 2 * phase : 2 - 2 * phase;
    ASSERT_TRUE(s.pose(60 * tri, 150 * tri, 180 * tri - 90));
    poses.emplace_back(s.engine().model.begin(), s.engine().model.end());
  }
  sinew::metaballs::reset(&s.state());
  const uint64_t before = s.state().stats.steps;
  const int steps = sinew::test::soak_enabled() ? 100000 : 2000;
  const sinew::skin::SkinnedVertices out = s.output();
  sinew::test::AllocationCounter allocations;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i)
    ASSERT_TRUE(sinew::metaballs::step(&s.state(), poses[static_cast<size_t>(i % kPeriod)], out).ok());
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "metaballs: %d steps (%u vertices, %u balls, jiggle, bulge, "
      "smoothing, overlap): %llu heap allocations, "
      "%.3f ms/step (this build)\n",
      steps, s.rig().vertex_count(), s.model().ball_count(), static_cast<unsigned long long>(allocations.allocations()),
      ms / steps);
  EXPECT_EQ(allocations.allocations(), 0u);
  EXPECT_EQ(s.state().stats.steps - before, static_cast<uint64_t>(steps));
}
