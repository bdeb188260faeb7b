// What the daemon derives from the rig and the config before its loop: the
// accepted range and timeout of every input, and the pipeline options.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "config.hpp"
#include "firmware/rig/loaded_rig.hpp"
#include "firmware/runtime/runtime.hpp"

namespace sinew::firmware {

// Accepted range per input: the DOF's limits widened by range_margin_deg
// (values in the margin are clamped by the engine and flagged; beyond it a
// sample is a sensor fault: rejected, counted, the last good value held).
// Timeout: timeout_factor x default period.
std::vector<InputLimits> input_limits(const LoadedRig& rig, const DaemonConfig& config, uint64_t tick_period_ns);

// The pipeline options from [layers] and [loop]: which of the rig's compiled
// layers run (the stage table names them). A layer switched on that the rig
// does not carry is refused with the layers it does carry.
bool layer_options(const DaemonConfig& config, const LoadedRig& rig, pipeline::PipelineOptions* out,
                   std::string* error);

// Whether the pipeline initialises with these options on this rig (the
// layers accept their models and the rate's gain conversion); false with
// the layer's message. Allocates its arena: start-up and checks only.
bool pipeline_accepts(const LoadedRig& rig, const pipeline::PipelineOptions& options, std::string* error);

}  // namespace sinew::firmware
