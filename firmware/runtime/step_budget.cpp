#include "step_budget.hpp"

#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <vector>

#include "hal/common/monotonic_clock.hpp"

namespace sinew::firmware {

namespace {

uint64_t probe_now(void*) { return hal::monotonic_ns(); }

// Untimed steps first: caches, page faults of the fresh arena, worker wake-up.
constexpr uint32_t kWarmupSteps = 8;
constexpr uint32_t kMinTimedSteps = 8;
// Steps for one sweep of an input across its range and back: the rig goes
// through its whole range a few times in a probe of a few hundred steps.
constexpr int64_t kSweepSteps = 128;

uint64_t percentile(std::vector<uint64_t> sorted, double p) {
  std::sort(sorted.begin(), sorted.end());
  const size_t i = std::min(sorted.size() - 1, static_cast<size_t>(p * static_cast<double>(sorted.size())));
  return sorted[i];
}

}  // namespace

int32_t swept_input(int32_t lo, int32_t hi, uint64_t step, size_t input) {
  const auto phase = static_cast<int64_t>((step + input * 37u) % kSweepSteps);
  const int64_t up = phase < kSweepSteps / 2 ? phase : kSweepSteps - phase;  // 0..kSweepSteps / 2
  return static_cast<int32_t>(lo + (int64_t{hi} - lo) * up / (kSweepSteps / 2));
}

bool probe_step(const rig::Rig& rig, const pipeline::LayerSet& layers, const pipeline::PipelineOptions& options,
                std::span<const InputLimits> limits, uint32_t steps, uint64_t wall_limit_ns, StepProbeResult* out,
                std::string* error) {
  if (limits.size() < rig.input_count + layers.external_count())
    return *error = "one input limit per rig input and per external input is required", false;
  std::vector<uint64_t> arena(pipeline::pipeline_state_bytes(rig, layers, options) / 8 + 1, 0);
  pipeline::Pipeline p;
  const pipeline::PipelineStatus ps = pipeline::pipeline_init(rig, layers, options, arena.data(), arena.size() * 8, &p);
  if (!ps.ok()) return *error = std::string("layers: ") + ps.message, false;
  // The sweep's range: a DOF's limits (the daemon's accepted range adds a
  // margin the engine clamps away); an external input's accepted range
  // without its margin of a tenth of the range on each side.
  std::vector<int32_t> lo(limits.size()), hi(limits.size());
  for (size_t k = 0; k < limits.size(); ++k) {
    const int64_t margin = (int64_t{limits[k].max} - limits[k].min) / 12;
    lo[k] = static_cast<int32_t>(limits[k].min + margin);
    hi[k] = static_cast<int32_t>(limits[k].max - margin);
  }
  for (const rig::JointRecord& j : rig.joints)
    for (uint32_t d = 0; d < j.dof_count; ++d)
      lo[j.first_input + d] = j.dof_min[d], hi[j.first_input + d] = j.dof_max[d];
  std::vector<int32_t> inputs(limits.size(), 0);
  std::vector<uint64_t> step_ns;
  step_ns.reserve(steps);
  uint64_t stage_total[pipeline::kStageCount] = {};
  const pipeline::StepProbe probe{probe_now, nullptr, nullptr};
  pipeline::StepReport report;
  const uint64_t began = hal::monotonic_ns();
  for (uint64_t s = 0; step_ns.size() < steps; ++s) {
    for (size_t k = 0; k < inputs.size(); ++k) inputs[k] = swept_input(lo[k], hi[k], s, k);
    const uint64_t t0 = hal::monotonic_ns();
    const pipeline::PipelineStatus st = pipeline::pipeline_step(&p, inputs, &probe, &report);
    const uint64_t t1 = hal::monotonic_ns();
    if (!st.ok()) return *error = std::string("layers: ") + st.message, false;
    if (s < kWarmupSteps) continue;
    step_ns.push_back(t1 - t0);
    for (uint32_t k = 0; k < pipeline::kStageCount; ++k) stage_total[k] += report.stage_ns[k];
    if (step_ns.size() >= kMinTimedSteps && t1 - began >= wall_limit_ns) break;
  }
  StepProbeResult r;
  r.steps = static_cast<uint32_t>(step_ns.size());
  r.p50_ns = percentile(step_ns, 0.50);
  r.p99_ns = percentile(step_ns, 0.99);
  r.max_ns = *std::max_element(step_ns.begin(), step_ns.end());
  name_slowest(stage_total, r.steps, &r);
  *out = r;
  return true;
}

void name_slowest(const uint64_t (&stage_total_ns)[pipeline::kStageCount], uint32_t steps, StepProbeResult* r) {
  r->slowest = pipeline::Stage::kSkinning;
  uint64_t largest = 0;
  for (uint32_t k = 0; k < pipeline::kStageCount; ++k)
    if (stage_total_ns[k] > largest) {
      largest = stage_total_ns[k];
      r->slowest = static_cast<pipeline::Stage>(k);
    }
  r->slowest_mean_ns = largest / steps;
  r->any_layer = false;
  r->slowest_layer = pipeline::Stage::kSkinning;
  uint64_t largest_layer = 0;
  for (uint32_t k = 0; k < pipeline::kStageCount; ++k)
    if (static_cast<pipeline::Stage>(k) != pipeline::Stage::kSkinning && stage_total_ns[k] > largest_layer) {
      largest_layer = stage_total_ns[k];
      r->slowest_layer = static_cast<pipeline::Stage>(k);
      r->any_layer = true;
    }
}

WakeProbeResult probe_wakeups(uint64_t interval_ns, uint32_t count) {
  std::vector<uint64_t> late;
  late.reserve(count);
  uint64_t deadline = hal::monotonic_ns() + interval_ns;
  for (uint32_t i = 0; i < count; ++i, deadline += interval_ns) {
    const timespec ts{static_cast<time_t>(deadline / 1'000'000'000u), static_cast<long>(deadline % 1'000'000'000u)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
    const uint64_t now = hal::monotonic_ns();
    late.push_back(now > deadline ? now - deadline : 0);
    // After a stall longer than the interval, the next deadline is in the
    // past: start again from now rather than count the stall twice.
    if (now > deadline + interval_ns) deadline = now;
  }
  return summarise_wakeups(late);
}

WakeProbeResult summarise_wakeups(std::span<const uint64_t> late_ns) {
  WakeProbeResult r;
  if (late_ns.empty()) return r;
  const std::vector<uint64_t> late(late_ns.begin(), late_ns.end());
  r.wakeups = static_cast<uint32_t>(late.size());
  r.p50_ns = percentile(late, 0.50);
  r.p99_ns = percentile(late, 0.99);
  r.max_ns = *std::max_element(late.begin(), late.end());
  uint64_t excess = 0, beyond = 0;
  for (const uint64_t l : late)
    if (l > r.p99_ns) excess += l - r.p99_ns, ++beyond;
  r.tail_scale_ns = beyond == 0 ? 0 : excess / beyond;
  return r;
}

uint64_t wake_lateness_at(const WakeProbeResult& wake, double probability) {
  constexpr double kThreshold = 0.01;  // the tail is fitted beyond p99
  constexpr double kSecondNs = 1e9;    // no tick waits out more (1 Hz is the slowest rate)
  if (probability >= kThreshold) return std::max(wake.p99_ns, wake.max_ns);
  const double x = probability <= 0 ? kSecondNs
                                    : static_cast<double>(wake.p99_ns) +
                                          static_cast<double>(wake.tail_scale_ns) * std::log(kThreshold / probability);
  return std::max(wake.max_ns, static_cast<uint64_t>(std::min(x, kSecondNs)));
}

namespace {

// P(X <= a) for a Poisson count X of mean lambda.
double poisson_at_most(uint64_t a, double lambda) {
  double term = std::exp(-lambda), sum = term;
  for (uint64_t k = 1; k <= a; ++k) term *= lambda / static_cast<double>(k), sum += term;
  return sum;
}

}  // namespace

double tolerated_miss_probability(const TickNeed& need, uint32_t rate_hz) {
  constexpr double kAllowed = 0.001;       // the verdict's 0.1 %
  constexpr double kShare = kAllowed / 2;  // of it, what a long run may expect
  constexpr double kRunsWithin = 0.9;      // nine runs in ten within the allowance
  if (need.duration_s <= 0) return kShare;
  const double ticks = std::max(1.0, std::floor(need.duration_s * rate_hz));
  const auto allowed = static_cast<uint64_t>(std::floor(kAllowed * ticks));
  // From a hundred allowed misses on, lambda / N is above the half share
  // (at 100: 87.6 / 100000), and exp(-lambda) would underflow further on.
  if (allowed >= 100) return kShare;
  // The largest lambda with P(X <= allowed) >= kRunsWithin, by bisection
  // (the probability falls monotonically in lambda).
  double lo = 0, hi = static_cast<double>(allowed) + 10;
  for (int i = 0; i < 60; ++i) {
    const double mid = (lo + hi) / 2;
    (poisson_at_most(allowed, mid) >= kRunsWithin ? lo : hi) = mid;
  }
  return std::min(kShare, lo / ticks);
}

uint64_t typical_tick_ns(const TickNeed& need) { return need.step_p99_ns + need.wake.p99_ns; }

uint64_t worst_tick_ns(const TickNeed& need, uint32_t rate_hz) {
  return need.step_p99_ns + wake_lateness_at(need.wake, tolerated_miss_probability(need, rate_hz));
}

uint32_t fitting_rate(uint32_t rate_hz, double share, const TickNeed& need) {
  const auto typical = static_cast<double>(typical_tick_ns(need));
  for (uint32_t k = 1; k <= rate_hz; ++k) {
    if (rate_hz % k != 0) continue;
    const uint32_t rate = rate_hz / k;
    const double period_ns = 1e9 / rate;
    if (typical <= share * period_ns && static_cast<double>(worst_tick_ns(need, rate)) <= period_ns) return rate;
  }
  return 0;
}

}  // namespace sinew::firmware
