// The daemon's sources: one registry entry per [[source]] type, with the
// keys parse_config checks (types, ranges) and the function that opens it.
// Adding a source type is its class (an hal::InputSource, in hal/<backend>
// or firmware/sources) plus one entry in sources.cpp.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "config.hpp"
#include "config_keys.hpp"
#include "firmware/rig/loaded_rig.hpp"
#include "firmware/runtime/runtime.hpp"
#include "hal/common/input_source.hpp"

namespace sinew::firmware {

// What a source is opened with besides its own table.
struct SourceSetup {
  const DaemonConfig& config;
  const LoadedRig& rig;
  uint64_t start_ns;  // the run's start on the monotonic clock (the schedule's origin)
};

struct SourceType {
  std::string_view type;            // [[source]] type = "..."
  std::span<const ConfigKey> keys;  // every key its table may hold
  // Opens the source; null with *error naming the source and key at fault.
  std::unique_ptr<hal::InputSource> (*open)(const SourceConfig& source, const SourceSetup& setup, std::string* error);
};

std::span<const SourceType> source_types();

// The rig input a source's sub-table names in its `input` key ("<joint>.<dof>"
// or an index); false with *error naming the source and `what`.input.
bool read_input(const SourceConfig& s, const toml::table& t, const LoadedRig& rig, const char* what, uint16_t* input,
                std::string* error);

// Opens one [[source]] through its registry entry; null with *error.
std::unique_ptr<hal::InputSource> open_source(const SourceConfig& source, const SourceSetup& setup, std::string* error);

// Opens every [[source]] of the config and adds it to the runtime.
bool add_sources(const DaemonConfig& config, const LoadedRig& rig, uint64_t start_ns, Runtime* runtime,
                 std::string* error);

}  // namespace sinew::firmware
