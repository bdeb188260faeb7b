#include "step_budget.hpp"

#include <time.h>

#include <algorithm>
#include <cerrno>
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
  WakeProbeResult r;
  if (late.empty()) return r;
  r.wakeups = count;
  r.p50_ns = percentile(late, 0.50);
  r.p99_ns = percentile(late, 0.99);
  r.max_ns = *std::max_element(late.begin(), late.end());
  return r;
}

uint32_t fitting_rate(uint32_t rate_hz, uint64_t typical_ns, double share, uint64_t worst_ns) {
  for (uint32_t k = 1; k <= rate_hz; ++k) {
    if (rate_hz % k != 0) continue;
    const uint32_t rate = rate_hz / k;
    const double period_ns = 1e9 / rate;
    if (static_cast<double>(typical_ns) <= share * period_ns && static_cast<double>(worst_ns) <= period_ns) return rate;
  }
  return 0;
}

}  // namespace sinew::firmware
