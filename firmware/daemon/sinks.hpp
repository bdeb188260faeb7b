// The daemon's sinks: one registry entry per [[sink]] type, with the keys
// parse_config checks (types, ranges) and the function that opens it.
// Adding a sink type is its class (an hal::OutputSink, in hal/output or
// firmware/sinks) plus one entry in sinks.cpp.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "config.hpp"
#include "config_keys.hpp"
#include "firmware/rig/loaded_rig.hpp"
#include "firmware/runtime/runtime.hpp"

namespace sinew::firmware {

// What a sink is opened with besides its own table.
struct SinkSetup {
  const DaemonConfig& config;
  const LoadedRig& rig;
  const pipeline::PipelineOptions& options;  // the pipeline as the runtime runs it
};

struct SinkType {
  std::string_view type;            // [[sink]] type = "..."
  std::span<const ConfigKey> keys;  // every key its table may hold
  // Opens the sink behind its I/O thread's queue, ready for the tick; null
  // with *error naming the sink and the problem.
  std::unique_ptr<OutputSink> (*open)(const SinkConfig& sink, const SinkSetup& setup, std::string* error);
};

std::span<const SinkType> sink_types();

// Opens every [[sink]] of the config and adds it to the runtime.
bool add_sinks(const DaemonConfig& config, const LoadedRig& rig, Runtime* runtime, std::string* error);

}  // namespace sinew::firmware
