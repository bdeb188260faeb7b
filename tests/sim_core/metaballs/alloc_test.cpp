// Zero heap allocations across thousands of metaballs steps, with every stage
// on: jiggle (in physical units at a converted tick rate, and per step),
// bulge, action lines, joint balls, smoothing and overlap.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <vector>

#include "arm_scene.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/soak.hpp"

namespace {

// Replays one period of a triangle wave through bend and twist (the engine's
// joint transforms computed first: the engine's own test covers its
// allocations) and counts the heap calls of the metaballs steps alone.
void expect_no_allocations(const sinew::metaballs_build::Options& o, uint32_t tick_hz, const char* label) {
  sinew::test::ArmScene s(sinew::rigc::SkinChoice::kDualQuaternion, o);
  ASSERT_TRUE(s.ok()) << s.error();
  if (tick_hz > 0) {
    ASSERT_TRUE(sinew::metaballs::set_tick_rate(&s.state(), tick_hz).ok());
  }
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
    ASSERT_TRUE(sinew::metaballs::metaballs_step(&s.state(), poses[static_cast<size_t>(i % kPeriod)], out).ok());
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "metaballs, %s: %d steps (%u vertices, %u balls, %zu action balls, jiggle at %u Hz): %llu heap "
      "allocations, %.3f ms/step (this build)\n",
      label, steps, s.rig().vertex_count(), s.model().ball_count(), s.model().action_balls.size(), s.state().tick_hz,
      static_cast<unsigned long long>(allocations.allocations()), ms / steps);
  EXPECT_EQ(allocations.allocations(), 0u) << label;
  EXPECT_EQ(s.state().stats.steps - before, static_cast<uint64_t>(steps)) << label;
}

sinew::metaballs_build::Options all_stages() {
  sinew::metaballs_build::Options o = sinew::test::arm_options();
  o.jiggle.push_back({"shoulder", 0.3, 0.7, 0.1});
  o.bulge.push_back({"shoulder", 0.3, 0.7, "shoulder", "elbow", 0.3});
  sinew::metaballs_build::ActionLineSpec line;
  line.origin = "shoulder";
  line.insertion = "elbow";
  line.side[1] = 0.03;
  line.reach = 0.04;
  o.action_lines.push_back(line);
  o.smoothing_passes = 2;
  return o;
}

}  // namespace

TEST(MetaballsAllocation, ZeroAllocationsAcrossThousandsOfStepsWithPhysicalJiggle) {
  // The default jiggle (physical units, built for 1 kHz) run at 250 Hz.
  expect_no_allocations(all_stages(), 250, "physical jiggle, action line, bulge, smoothing, overlap");
}

TEST(MetaballsAllocation, ZeroAllocationsAcrossThousandsOfStepsWithPerStepJiggle) {
  sinew::metaballs_build::Options o = all_stages();
  o.jiggle_frequency = 0;
  expect_no_allocations(o, 0, "per-step jiggle, action line, bulge, smoothing, overlap");
}
