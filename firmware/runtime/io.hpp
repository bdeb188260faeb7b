// The runtime composes hal's input sources and output sinks; their interface
// and the per-input health live in hal/common so backends need no firmware.
#pragma once

#include "hal/common/input_health.hpp"
#include "hal/common/input_source.hpp"
#include "hal/common/output_sink.hpp"

namespace sinew::firmware {

using hal::InputCounters;
using hal::InputHealth;
using hal::InputLimits;
using hal::InputSource;
using hal::OutputSink;
using hal::source_state_name;
using hal::SourceState;

}  // namespace sinew::firmware
