#include "step_fit.hpp"

#include <algorithm>
#include <cstdio>

#include "firmware/runtime/step_budget.hpp"
#include "sim_core/pipeline/stage_table.hpp"

namespace sinew::firmware {

namespace {

// A few hundred steps or a third of a second: p99 from enough samples to
// see the tail, without delaying the start noticeably.
constexpr uint32_t kProbeSteps = 400;
constexpr uint64_t kProbeWallNs = 300'000'000;
// A thousand wake-ups, at the tick's period or every millisecond when the
// period is longer (a second at most): a vCPU stall of a few milliseconds
// every second or so shows in the maximum more often than not.
constexpr uint32_t kWakeups = 1000;
constexpr uint64_t kWakeIntervalMaxNs = 1'000'000;

std::string us(uint64_t ns) {
  char s[32];
  std::snprintf(s, sizeof(s), "%.1f us", static_cast<double>(ns) / 1000.0);
  return s;
}

}  // namespace

bool fit_step_to_budget(DaemonConfig* config, const LoadedRig& rig, std::span<const InputLimits> limits,
                        pipeline::PipelineOptions* options, StepFit* fit, std::string* error) {
  fit->configured_hz = fit->rate_hz = config->rate_hz;
  fit->report.clear();
  StepProbeResult step;
  if (!probe_step(rig.rig, rig.layers, *options, limits, kProbeSteps, kProbeWallNs, &step, error)) return false;
  const uint64_t period_ns = 1'000'000'000u / config->rate_hz;
  const WakeProbeResult wake = probe_wakeups(std::min(period_ns, kWakeIntervalMaxNs), kWakeups);
  // A live tick is a wake-up after its deadline, then a step: typically
  // both at their p99 within step_budget of the period, and the stall the
  // wake-ups' tail expects as often as the run may miss a deadline, with a
  // p99 step, within the period (step_budget.hpp, TickNeed).
  const double share = config->step_budget;
  const TickNeed need{step.p99_ns, wake, config->duration_s};
  const uint64_t typical_ns = typical_tick_ns(need), worst_ns = worst_tick_ns(need, config->rate_hz);
  const auto budget_ns = static_cast<uint64_t>(share * static_cast<double>(period_ns));
  const std::string slowest =
      std::string(pipeline::stage_name(step.slowest)) + " " + us(step.slowest_mean_ns) + " mean";
  char line[720];
  std::snprintf(line, sizeof(line),
                "sinewd: at start-up: step (%u steps, inputs swept over their ranges) p50 %s, p99 %s, max %s, slowest "
                "stage %s; timer wake-ups (%u) late by p50 %s, p99 %s, max %s, beyond p99 %s on average\n",
                step.steps, us(step.p50_ns).c_str(), us(step.p99_ns).c_str(), us(step.max_ns).c_str(), slowest.c_str(),
                wake.wakeups, us(wake.p50_ns).c_str(), us(wake.p99_ns).c_str(), us(wake.max_ns).c_str(),
                us(wake.tail_scale_ns).c_str());
  fit->report = line;
  if (typical_ns <= budget_ns && worst_ns <= period_ns) return true;
  const uint32_t fitting = fitting_rate(config->rate_hz, share, need);
  char once_in[64];
  std::snprintf(once_in, sizeof(once_in), "%.0f", 1.0 / tolerated_miss_probability(need, config->rate_hz));
  const std::string over = "a tick needs " + us(typical_ns) + " at p99 and " + us(worst_ns) +
                           " at worst (the stall the wake-ups' tail expects once in " + once_in +
                           " ticks), against a budget of " + us(budget_ns) + " (step_budget " +
                           std::to_string(share).substr(0, 4) + ") and a period of " + us(period_ns) + " at " +
                           std::to_string(config->rate_hz) + " Hz";
  const std::string remedies =
      (fitting > 0 ? "[loop] over_budget = \"slow\" would run at " + std::to_string(fitting) + " Hz; " : "") +
      "or lower [loop] rate_hz" +
      // Skinning is always on: the remedy names the slowest layer that a
      // [layers] key switches off, whichever stage was slowest.
      (step.any_layer ? std::string(", or switch off [layers] ") + pipeline::stage_name(step.slowest_layer) : "");
  switch (config->over_budget) {
    case OverBudget::kWarn:
      fit->report += "sinewd: warning: " + over + ": expect deadline misses (" + remedies + ")\n";
      return true;
    case OverBudget::kRefuse:
      return *error = "[loop] over_budget = \"refuse\": " + over + " (" + remedies + ")", false;
    case OverBudget::kSlow:
      break;
  }
  if (fitting == 0) {
    fit->report += "sinewd: warning: " + over + ", and no exact divisor of the rate down to 1 Hz fits: running at " +
                   std::to_string(config->rate_hz) + " Hz\n";
    return true;
  }
  // The layers convert their rate-dependent gains at init: the slower rate
  // must be one they accept (a stiff spring may not be stable at it).
  pipeline::PipelineOptions slower = *options;
  slower.tick_hz = fitting;
  StepProbeResult check;
  std::string refused;
  if (!probe_step(rig.rig, rig.layers, slower, limits, 1, 0, &check, &refused)) {
    fit->report += "sinewd: warning: " + over + "; the layers refuse " + std::to_string(fitting) + " Hz (" + refused +
                   "): running at " + std::to_string(config->rate_hz) + " Hz\n";
    return true;
  }
  fit->report += "sinewd: slowed to " + std::to_string(fitting) + " Hz ([loop] over_budget = \"slow\"): " + over +
                 "; the fastest exact divisor of the rate that fits\n";
  fit->rate_hz = config->rate_hz = fitting;
  *options = slower;
  return true;
}

}  // namespace sinew::firmware
