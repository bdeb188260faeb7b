// The start-up probe of the tick (firmware/runtime/step_budget.hpp): the
// rate chosen to fit, the input sweep, and the probes' results. Timing
// values are only checked for their order (p50 <= p99 <= max), which holds
// under any load.
#include "firmware/runtime/step_budget.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "firmware/daemon/config.hpp"
#include "firmware/daemon/run_setup.hpp"
#include "firmware/rig/loaded_rig.hpp"

namespace step_budget_test {

using sinew::firmware::fitting_rate;

constexpr uint64_t kUs = 1000;

TEST(FittingRate, KeepsTheRateWhenTheTickFits) {
  EXPECT_EQ(fitting_rate(1000, 400 * kUs, 0.5, 900 * kUs), 1000u);
  EXPECT_EQ(fitting_rate(1000, 500 * kUs, 0.5, 1000 * kUs), 1000u);  // both bounds inclusive
}

TEST(FittingRate, TheTypicalTickWithinTheShareOfThePeriod) {
  // 600 us within half the period: a period of 1.2 ms at least, 2 ms the
  // first exact divisor of 1000 Hz.
  EXPECT_EQ(fitting_rate(1000, 600 * kUs, 0.5, 900 * kUs), 500u);
  // 1.1 ms within half: 2.2 ms at least; 1000 / 3 is no exact divisor, so 250.
  EXPECT_EQ(fitting_rate(1000, 1100 * kUs, 0.5, 1100 * kUs), 250u);
  EXPECT_EQ(fitting_rate(1000, 600 * kUs, 1.0, 600 * kUs), 1000u);
}

TEST(FittingRate, TheWorstTickWithinThePeriod) {
  // A 3.8 ms stall seen at start-up: the period must hold it.
  EXPECT_EQ(fitting_rate(1000, 400 * kUs, 0.5, 3800 * kUs), 250u);
  EXPECT_EQ(fitting_rate(1000, 400 * kUs, 0.5, 4100 * kUs), 200u);
}

TEST(FittingRate, OnlyExactDivisorsAndZeroWhenNothingFits) {
  // 997 is prime: its divisors are 997 and 1.
  EXPECT_EQ(fitting_rate(997, 2 * kUs * 1000, 0.5, 2 * kUs * 1000), 1u);
  EXPECT_EQ(fitting_rate(1000, 2'000'000 * kUs, 0.5, 0), 0u);
  for (uint64_t typical = 100 * kUs; typical < 100'000 * kUs; typical = typical * 3 / 2) {
    const uint32_t r = fitting_rate(1000, typical, 0.5, typical);
    ASSERT_GT(r, 0u);
    EXPECT_EQ(1000u % r, 0u) << r;
    EXPECT_LE(static_cast<double>(typical), 0.5 * 1e9 / r) << r;
  }
}

TEST(SweptInput, CoversTheRangeEndsAndPhasesDiffer) {
  const int32_t lo = -1000000, hi = 3000000;
  int32_t seen_lo = hi, seen_hi = lo;
  bool differ = false;
  for (uint64_t s = 0; s < 128; ++s) {
    const int32_t v = sinew::firmware::swept_input(lo, hi, s, 0);
    ASSERT_GE(v, lo);
    ASSERT_LE(v, hi);
    seen_lo = std::min(seen_lo, v);
    seen_hi = std::max(seen_hi, v);
    differ |= v != sinew::firmware::swept_input(lo, hi, s, 1);
  }
  EXPECT_EQ(seen_lo, lo);
  EXPECT_EQ(seen_hi, hi);
  EXPECT_TRUE(differ);
}

TEST(ProbeStep, TimesTheArmsLayersAndNamesTheSlowest) {
  sinew::firmware::LoadedRig rig;
  std::string error;
  ASSERT_TRUE(sinew::firmware::load_rig("arm", "", &rig, &error)) << error;
  sinew::firmware::DaemonConfig config;
  config.layers.stages.set(sinew::pipeline::Stage::kMetaballs, true);
  sinew::pipeline::PipelineOptions options;
  ASSERT_TRUE(sinew::firmware::layer_options(config, rig, &options, &error)) << error;
  const auto limits = sinew::firmware::input_limits(rig, config, 1'000'000);
  sinew::firmware::StepProbeResult r;
  ASSERT_TRUE(sinew::firmware::probe_step(rig.rig, rig.layers, options, limits, 20, 10'000'000'000u, &r, &error))
      << error;
  EXPECT_EQ(r.steps, 20u);
  EXPECT_LE(r.p50_ns, r.p99_ns);
  EXPECT_LE(r.p99_ns, r.max_ns);
  // Which stage is slowest depends on the machine and its load; only what
  // holds under any scheduling: a stage that ran, whose mean lies within a
  // step (each stage's time is part of its step's).
  EXPECT_TRUE(r.slowest == sinew::pipeline::Stage::kSkinning || r.slowest == sinew::pipeline::Stage::kMetaballs);
  EXPECT_GT(r.slowest_mean_ns, 0u);
  EXPECT_LE(r.slowest_mean_ns, r.max_ns);
}

// The naming itself, on given totals: the largest total, the first of
// equal ones, its mean over the steps.
TEST(ProbeStep, NamesTheStageWithTheLargestTotal) {
  namespace pl = sinew::pipeline;
  static_assert(pl::kStageCount == 5);
  sinew::firmware::StepProbeResult r;
  const uint64_t metaballs_slowest[pl::kStageCount] = {4000, 100, 9000, 600, 0};
  sinew::firmware::name_slowest(metaballs_slowest, 10, &r);
  EXPECT_EQ(r.slowest, pl::Stage::kMetaballs);
  EXPECT_EQ(r.slowest_mean_ns, 900u);
  const uint64_t tie[pl::kStageCount] = {0, 700, 100, 700, 700};
  sinew::firmware::name_slowest(tie, 7, &r);
  EXPECT_EQ(r.slowest, pl::Stage::kSph);
  EXPECT_EQ(r.slowest_mean_ns, 100u);
  const uint64_t last[pl::kStageCount] = {1, 2, 3, 4, 50};
  sinew::firmware::name_slowest(last, 5, &r);
  EXPECT_EQ(r.slowest, pl::Stage::kAnatomy);
  EXPECT_EQ(r.slowest_mean_ns, 10u);
}

TEST(ProbeStep, RefusesTooFewInputLimits) {
  sinew::firmware::LoadedRig rig;
  std::string error;
  ASSERT_TRUE(sinew::firmware::load_rig("arm", "", &rig, &error)) << error;
  sinew::firmware::StepProbeResult r;
  EXPECT_FALSE(sinew::firmware::probe_step(rig.rig, rig.layers, {}, {}, 20, 0, &r, &error));
  EXPECT_NE(error.find("input limit"), std::string::npos) << error;
}

TEST(ProbeWakeups, RecordsEveryWakeUp) {
  const sinew::firmware::WakeProbeResult w = sinew::firmware::probe_wakeups(200 * kUs, 25);
  EXPECT_EQ(w.wakeups, 25u);
  EXPECT_LE(w.p50_ns, w.p99_ns);
  EXPECT_LE(w.p99_ns, w.max_ns);
}

}  // namespace step_budget_test
