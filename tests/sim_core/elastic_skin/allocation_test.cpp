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

// The dynamic skin, both integrators (LEMAN's relaxation with bend, air
// pressure and reactions; the explicit substeps): no heap after init, and
// the relaxation's work per tick fixed (one step of exactly its sweeps).
TEST(AnatomyAllocation, DynamicSkinStepsNeverTouchTheHeap) {
  for (const bool relaxation : {true, false}) {
    ArmAnatomy arm([&](sinew::anatomy_build::AnatomySpec& s) {
      s.skin.solver.dynamic = true;
      s.skin.solver.relaxation = relaxation;
      s.skin.solver.pressure = 20.0;
      s.skin.solver.gravity[1] = -9.81;
    });
    ASSERT_TRUE(arm.ok()) << arm.error();
    const int steps = sinew::test::soak_enabled() ? 20000 : (sinew::test::emulated() ? 50 : 300);
    const size_t elbow = static_cast<size_t>(arm.input("elbow.0"));
    sinew::test::AllocationCounter counter;
    uint32_t failures = 0, reactions = 0, other_sweeps = 0;
    for (int s = 0; s < steps; ++s) {
      arm.inputs()[elbow] = sinew::test::deg((s * 7) % 150);
      failures += !arm.step().ok();
      reactions += arm.skin().stats.reactions;
      if (relaxation) other_sweeps += arm.skin().stats.iterations != arm.skin_model().surface.relaxation_iterations;
    }
    std::printf("%d steps (engine + muscles + dynamic skin, %s): %llu heap allocations, %u reactions\n", steps,
                relaxation ? "relaxation" : "explicit", static_cast<unsigned long long>(counter.allocations()),
                reactions);
    EXPECT_EQ(failures, 0u);
    EXPECT_EQ(counter.allocations(), 0u);
    EXPECT_EQ(other_sweeps, 0u) << "every relaxation step runs exactly its sweeps";
    EXPECT_GT(reactions, 0u);
  }
}
