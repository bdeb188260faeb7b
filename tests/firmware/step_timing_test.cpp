#include "firmware/runtime/step_timing.hpp"

#include <gtest/gtest.h>

TEST(StepTiming, PercentilesWithinOneSixteenth) {
  sinew::firmware::StepTiming t;
  for (uint64_t i = 1; i <= 1000; ++i) t.record(i * 1000, i > 990);
  EXPECT_EQ(t.count(), 1000u);
  EXPECT_EQ(t.max_ns(), 1000000u);
  EXPECT_EQ(t.deadline_misses(), 10u);
  const double p50 = static_cast<double>(t.percentile_ns(0.5));
  const double p99 = static_cast<double>(t.percentile_ns(0.99));
  EXPECT_NEAR(p50, 500000, 500000 / 16.0);
  EXPECT_NEAR(p99, 990000, 990000 / 16.0);
  EXPECT_LE(t.percentile_ns(1.0), t.max_ns());
}
