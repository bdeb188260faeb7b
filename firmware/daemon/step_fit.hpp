// [loop] step_budget and over_budget: before a live run starts, the daemon
// times its own step on the machine it runs on (firmware/runtime/
// step_budget.hpp) and, when the step's p99 takes more than step_budget of
// the period, warns, refuses to start, or slows the rate to the fastest
// exact divisor of rate_hz it fits (docs/pipeline.md, "Fitting the tick to
// the machine").
#pragma once

#include <span>
#include <string>

#include "config.hpp"
#include "firmware/rig/loaded_rig.hpp"
#include "firmware/runtime/runtime.hpp"

namespace sinew::firmware {

struct StepFit {
  uint32_t configured_hz = 0;  // [loop] rate_hz as configured
  uint32_t rate_hz = 0;        // the rate the run uses (lower when slowed)
  std::string report;          // what was measured and decided, lines ending in '\n'
};

// Measures and applies the policy: with over_budget = "slow" it may lower
// config->rate_hz and options->tick_hz. False with `error` (naming the
// measured step, the budget and the slowest stage) for "refuse", or when the
// pipeline refuses the options.
bool fit_step_to_budget(DaemonConfig* config, const LoadedRig& rig, std::span<const InputLimits> limits,
                        pipeline::PipelineOptions* options, StepFit* fit, std::string* error);

}  // namespace sinew::firmware
