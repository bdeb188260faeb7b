#include "hal/gpio/debounce.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "tests/support/time_units.hpp"

namespace sinew::hal::gpio {
namespace {

using sinew::test::kUs;

TEST(Debouncer, BouncingPressIsOneChangeAfterTheLastEdge) {
  Debouncer d;
  d.reset(false, 1000 * kUs);
  // Press at t = 10 ms with five bounces 100 us apart, then held.
  uint64_t t = 10'000 * kUs;
  bool level = true;
  for (int i = 0; i < 9; ++i, t += 100 * kUs, level = !level) d.on_edge(level, t);
  const uint64_t last_edge = t - 100 * kUs;
  EXPECT_FALSE(d.settle(last_edge + 999 * kUs));
  EXPECT_FALSE(d.stable());
  EXPECT_TRUE(d.settle(last_edge + 1000 * kUs));
  EXPECT_TRUE(d.stable());
  EXPECT_EQ(d.changed_ns(), last_edge + 1000 * kUs);
  std::printf("9 edges in 0.8 ms: %llu change(s), %llu bounces, accepted %.3f ms after the last edge\n",
              static_cast<unsigned long long>(d.changes()), static_cast<unsigned long long>(d.bounces()),
              static_cast<double>(d.changed_ns() - last_edge) / 1e6);
  EXPECT_EQ(d.changes(), 1u);
  EXPECT_EQ(d.bounces(), 4u);  // the four returns to the old level cancelled a pending change
}

TEST(Debouncer, ShortGlitchNeverChangesTheLevel) {
  Debouncer d;
  d.reset(true, 500 * kUs);
  d.on_edge(false, 1000 * kUs);
  d.on_edge(true, 1400 * kUs);  // 0.4 ms low: shorter than the debounce
  EXPECT_FALSE(d.settle(100'000 * kUs));
  EXPECT_TRUE(d.stable());
  EXPECT_EQ(d.changes(), 0u);
}

TEST(Debouncer, AnEdgeProvesTheHoldWithoutALatch) {
  Debouncer d;
  d.reset(false, 500 * kUs);
  d.on_edge(true, 1000 * kUs);
  d.on_edge(false, 2000 * kUs);  // high held 1 ms: accepted at 1.5 ms, then a new pending change
  EXPECT_TRUE(d.stable());
  EXPECT_EQ(d.changed_ns(), 1500 * kUs);
  EXPECT_TRUE(d.settle(2500 * kUs));
  EXPECT_FALSE(d.stable());
  EXPECT_EQ(d.changes(), 2u);
}

TEST(Debouncer, ZeroDebounceFollowsEveryEdge) {
  Debouncer d;
  d.reset(false, 0);
  d.on_edge(true, 10);
  EXPECT_TRUE(d.settle(10));
  EXPECT_TRUE(d.stable());
}

}  // namespace
}  // namespace sinew::hal::gpio
