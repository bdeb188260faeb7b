// The start-up probe of the tick (firmware/runtime/step_budget.hpp): the
// rate chosen to fit, the input sweep, and the probes' results. Timing
// values are only checked for their order (p50 <= p99 <= max), which holds
// under any load.
#include "firmware/runtime/step_budget.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "firmware/daemon/config.hpp"
#include "firmware/daemon/run_setup.hpp"
#include "firmware/rig/loaded_rig.hpp"

namespace step_budget_test {

using sinew::firmware::fitting_rate;
using sinew::firmware::TickNeed;
using sinew::firmware::WakeProbeResult;

constexpr uint64_t kUs = 1000;

// A need whose wake-ups have no tail beyond their largest lateness: the
// worst tick is the p99 step plus that lateness at every rate.
TickNeed no_tail(uint64_t step_p99_ns, uint64_t wake_p99_ns, uint64_t wake_max_ns) {
  TickNeed need;
  need.step_p99_ns = step_p99_ns;
  need.wake.p99_ns = wake_p99_ns;
  need.wake.max_ns = wake_max_ns;
  return need;
}

TEST(FittingRate, KeepsTheRateWhenTheTickFits) {
  EXPECT_EQ(fitting_rate(1000, 0.5, no_tail(300 * kUs, 100 * kUs, 600 * kUs)), 1000u);
  EXPECT_EQ(fitting_rate(1000, 0.5, no_tail(400 * kUs, 100 * kUs, 600 * kUs)), 1000u);  // both bounds inclusive
}

TEST(FittingRate, TheTypicalTickWithinTheShareOfThePeriod) {
  // 600 us within half the period: a period of 1.2 ms at least, 2 ms the
  // first exact divisor of 1000 Hz.
  EXPECT_EQ(fitting_rate(1000, 0.5, no_tail(500 * kUs, 100 * kUs, 400 * kUs)), 500u);
  // 1.1 ms within half: 2.2 ms at least; 1000 / 3 is no exact divisor, so 250.
  EXPECT_EQ(fitting_rate(1000, 0.5, no_tail(1000 * kUs, 100 * kUs, 100 * kUs)), 250u);
  EXPECT_EQ(fitting_rate(1000, 1.0, no_tail(500 * kUs, 100 * kUs, 100 * kUs)), 1000u);
}

TEST(FittingRate, TheWorstWakeUpSeenWithinThePeriod) {
  // A 3.4 ms stall seen at start-up after a 400 us step: the period must
  // hold 3.8 ms.
  EXPECT_EQ(fitting_rate(1000, 0.5, no_tail(400 * kUs, 0, 3400 * kUs)), 250u);
  EXPECT_EQ(fitting_rate(1000, 0.5, no_tail(400 * kUs, 0, 3700 * kUs)), 200u);
}

// The stall the tail expects, not only the one seen: a machine whose
// wake-ups beyond p99 are late by 1.4 ms more on average (a virtual
// machine's vCPU stalls) needs 125 Hz for a 5 s run that misses no
// deadline; the largest stall its probe saw (2 ms) alone would allow 250 Hz.
TEST(FittingRate, TheStallTheTailExpectsWithinThePeriod) {
  TickNeed need = no_tail(500 * kUs, 500 * kUs, 2000 * kUs);
  need.duration_s = 5;
  EXPECT_EQ(fitting_rate(1000, 0.5, need), 250u);
  need.wake.tail_scale_ns = 1400 * kUs;
  // 125 Hz: 625 ticks may miss none, p = 0.105 / 625; the stall at p is
  // 0.5 + 1.4 ln(0.01 / p) = 6.2 ms, after a 0.5 ms step: within 8 ms.
  // 200 Hz: p = 0.0005 (the half share), 0.5 + 1.4 ln 20 + 0.5 = 5.2 ms > 5.
  EXPECT_EQ(fitting_rate(1000, 0.5, need), 125u);
  EXPECT_GT(sinew::firmware::worst_tick_ns(need, 200), 5000 * kUs);
  EXPECT_LE(sinew::firmware::worst_tick_ns(need, 125), 8000 * kUs);
}

TEST(FittingRate, OnlyExactDivisorsAndZeroWhenNothingFits) {
  // 997 is prime: its divisors are 997 and 1.
  EXPECT_EQ(fitting_rate(997, 0.5, no_tail(2000 * kUs, 0, 0)), 1u);
  EXPECT_EQ(fitting_rate(1000, 0.5, no_tail(2'000'000 * kUs, 0, 0)), 0u);
  for (uint64_t typical = 100 * kUs; typical < 100'000 * kUs; typical = typical * 3 / 2) {
    const uint32_t r = fitting_rate(1000, 0.5, no_tail(typical, 0, 0));
    ASSERT_GT(r, 0u);
    EXPECT_EQ(1000u % r, 0u) << r;
    EXPECT_LE(static_cast<double>(typical), 0.5 * 1e9 / r) << r;
  }
}

TEST(ToleratedMissProbability, NoMissInAShortRunHalfTheShareInALongOne) {
  TickNeed need;
  EXPECT_DOUBLE_EQ(sinew::firmware::tolerated_miss_probability(need, 1000), 0.0005);  // endless
  need.duration_s = 5;
  // 625 ticks may miss none: P(no miss) = exp(-lambda) = 0.9.
  EXPECT_NEAR(sinew::firmware::tolerated_miss_probability(need, 125), -std::log(0.9) / 625, 1e-9);
  // 1250 ticks may miss one: exp(-l) (1 + l) = 0.9 at l = 0.5318.
  EXPECT_NEAR(sinew::firmware::tolerated_miss_probability(need, 250), 0.531812 / 1250, 1e-8);
  // 5000 ticks may miss five; lambda / N = 3.15 / 5000 is above the half share.
  EXPECT_DOUBLE_EQ(sinew::firmware::tolerated_miss_probability(need, 1000), 0.0005);
  need.duration_s = 1e7;  // a hundred allowed misses and more: the half share
  EXPECT_DOUBLE_EQ(sinew::firmware::tolerated_miss_probability(need, 1000), 0.0005);
}

TEST(WakeTail, MeanExcessBeyondP99AndTheExtrapolatedLateness) {
  // 1000 wake-ups: 990 late by 10 us, ten by 20..200 us.
  std::vector<uint64_t> late(990, 10 * kUs);
  for (uint64_t k = 1; k <= 10; ++k) late.push_back(20 * k * kUs);
  const WakeProbeResult w = sinew::firmware::summarise_wakeups(late);
  EXPECT_EQ(w.wakeups, 1000u);
  EXPECT_EQ(w.p50_ns, 10 * kUs);
  EXPECT_EQ(w.p99_ns, 20 * kUs);  // index 990 of the sorted lateness
  EXPECT_EQ(w.max_ns, 200 * kUs);
  EXPECT_EQ(w.tail_scale_ns, 100 * kUs);  // (20 + 40 + ... + 180) / 9 - 20
  // At or above 1 %: the largest lateness seen.
  EXPECT_EQ(sinew::firmware::wake_lateness_at(w, 0.01), 200 * kUs);
  // Below: p99 + scale ln(0.01 / p), never under the largest seen.
  EXPECT_EQ(sinew::firmware::wake_lateness_at(w, 0.005), 200 * kUs);  // 20 + 100 ln 2 = 89 us
  EXPECT_NEAR(static_cast<double>(sinew::firmware::wake_lateness_at(w, 0.001)), 20e3 + 100e3 * std::log(10.0), 1.0);
  EXPECT_NEAR(static_cast<double>(sinew::firmware::wake_lateness_at(w, 1e-5)), 20e3 + 100e3 * std::log(1000.0), 1.0);
  EXPECT_EQ(sinew::firmware::wake_lateness_at(w, 0), 1'000'000'000u);  // capped at a second
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
  EXPECT_TRUE(r.any_layer);
  EXPECT_EQ(r.slowest_layer, pl::Stage::kAnatomy);
}

// The layer an over-budget message tells the user to switch off is never
// skinning, which no [layers] key switches off: the slowest of the others
// that ran, or none.
TEST(ProbeStep, NamesTheSlowestLayerThatCanBeSwitchedOff) {
  namespace pl = sinew::pipeline;
  static_assert(pl::kStageCount == 5);
  sinew::firmware::StepProbeResult r;
  const uint64_t skinning_slowest[pl::kStageCount] = {9000, 0, 300, 500, 0};
  sinew::firmware::name_slowest(skinning_slowest, 10, &r);
  EXPECT_EQ(r.slowest, pl::Stage::kSkinning);
  EXPECT_TRUE(r.any_layer);
  EXPECT_EQ(r.slowest_layer, pl::Stage::kBarnet);
  const uint64_t metaballs_slowest[pl::kStageCount] = {4000, 100, 9000, 600, 0};
  sinew::firmware::name_slowest(metaballs_slowest, 10, &r);
  EXPECT_TRUE(r.any_layer);
  EXPECT_EQ(r.slowest_layer, pl::Stage::kMetaballs);
  const uint64_t skinning_only[pl::kStageCount] = {700, 0, 0, 0, 0};
  sinew::firmware::name_slowest(skinning_only, 7, &r);
  EXPECT_EQ(r.slowest, pl::Stage::kSkinning);
  EXPECT_FALSE(r.any_layer);
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
