// The daemon's own keys ([loop], [realtime], [inputs], [status]; [rig] names
// the rig): each declared once, with its default as TOML, one line of
// documentation, and how to read its resolved value back from a parsed
// DaemonConfig. parse_config accepts exactly these keys; `sinewd
// --print-default-config` prints them with their defaults and `sinewd
// --check-config FILE` with a file's values. A test holds every default to
// what parse_config gives a file that does not set the key, so the printed
// defaults cannot drift from the parser. [layers] keys come from the stage
// table (sim_core/pipeline/stage_table.hpp), [[source]] and [[sink]] keys
// from their registries (sources.cpp, sinks.cpp).
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "config.hpp"

namespace sinew::firmware {

struct DaemonKey {
  std::string_view table;  // "loop", "realtime", ...
  std::string_view key;
  std::string_view default_toml;                // the value parse_config uses when the key is absent, as TOML
  std::string_view doc;                         // one line
  std::string (*value)(const DaemonConfig& c);  // the resolved value, as TOML
};

std::span<const DaemonKey> daemon_keys();
// The keys of one table, in declaration order.
std::vector<std::string_view> daemon_keys_of(std::string_view table);

// Every daemon key with its default and documentation, [layers] with every
// stage off and its options' defaults, and pointers to the source and sink
// types: what `sinewd --print-default-config` writes.
std::string default_config_text();

// A parsed configuration with every daemon key and [layers] key resolved
// (defaults filled in), followed by its [[source]] and [[sink]] tables as
// given: what `sinewd --check-config` prints.
std::string resolved_config_text(const DaemonConfig& c);

}  // namespace sinew::firmware
