// Builds the runtime's sources and sinks from the config, and the input
// limits from the rig; prints the periodic report.
#pragma once

#include <string>
#include <vector>

#include "config.hpp"
#include "firmware/runtime/runtime.hpp"
#include "loaded_rig.hpp"

namespace sinew::firmware {

// Accepted range per input: the DOF's limits widened by range_margin_deg
// (values in the margin are clamped by the engine and flagged; beyond it a
// sample is a sensor fault: rejected, counted, the last good value held).
// Timeout: timeout_factor x default period.
std::vector<InputLimits> input_limits(const LoadedRig& rig, const DaemonConfig& config, uint64_t tick_period_ns);

bool add_sources(const DaemonConfig& config, const LoadedRig& rig, uint64_t tick_period_ns, uint64_t start_ns,
                 Runtime* runtime, std::string* error);
// The pipeline options from [layers] and [loop]: which of the rig's compiled
// layers run. A layer switched on that the rig does not carry is refused
// with the layers it does carry.
bool layer_options(const DaemonConfig& config, const LoadedRig& rig, pipeline::PipelineOptions* out,
                   std::string* error);
bool add_sinks(const DaemonConfig& config, const LoadedRig& rig, Runtime* runtime, std::string* error);

void print_stats(Runtime& runtime, const LoadedRig& rig, bool final_report);

}  // namespace sinew::firmware
