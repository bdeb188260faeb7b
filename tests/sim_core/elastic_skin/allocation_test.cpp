// Zero heap allocations across thousands of layer steps (after init).
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/sim_core/muscle/anatomy_fixture.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/soak.hpp"

using sinew::test::ArmAnatomy;

TEST(AnatomyAllocation, StepsNeverTouchTheHeap) {
  // LEMAN's regime: a few warm-started relaxations per step.
  ArmAnatomy arm([](sinew::anatomy_build::AnatomySpec& s) {
    s.skin.iterations = 2;
    s.skin.warm_start = true;
  });
  ASSERT_TRUE(arm.ok()) << arm.error();
  // 1000 steps natively; 250 under qemu (about 100 ms a step on armhf).
  const int steps = sinew::test::soak_enabled() ? 100000 : (sinew::test::emulated() ? 250 : 1000);
  const size_t elbow = static_cast<size_t>(arm.input("elbow.0")),
               shoulder = static_cast<size_t>(arm.input("shoulder.0"));
  sinew::test::AllocationCounter counter;
  uint32_t failures = 0, reactions = 0;
  for (int s = 0; s < steps; ++s) {
    arm.inputs()[elbow] = sinew::test::deg((s * 7) % 150);
    arm.inputs()[shoulder] = sinew::test::deg((s * 3) % 90 - 45);
    failures += !arm.step().ok();
    reactions += arm.skin().stats.reactions;
  }
  std::printf("%d steps (engine + muscles + skin, 2 warm relaxations each): %llu heap allocations, %u reactions\n",
              steps, static_cast<unsigned long long>(counter.allocations()), reactions);
  EXPECT_EQ(failures, 0u);
  EXPECT_EQ(counter.allocations(), 0u);
}
