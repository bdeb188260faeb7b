// The keys of a [[source]] or [[sink]] type and of their sub-tables, with
// their types and ranges. Each type declares them once, in its registry
// entry (sources.cpp, sinks.cpp); parse_config checks every table against
// them where the file and line are known, so the factories convert only
// values that fit.
#pragma once

#include <span>
#include <string_view>

namespace sinew::firmware {

enum class KeyKind {
  kString,
  kFlag,
  kInteger,  // an integer in [lo, hi]
  kNumber,   // a finite number in [lo, hi]
  kInput,    // a rig input, by name or index
  kTables,   // [[sub-tables]], each checked against sub
  kTable,    // a [sub-table], checked against sub
  kChoice,   // one of the strings in choices
};

struct ConfigKey {
  std::string_view name;
  KeyKind kind;
  double lo = 0, hi = 0;
  std::span<const ConfigKey> sub = {};
  std::span<const std::string_view> choices = {};
};

inline constexpr double kMaxPort = 65535, kMaxMs = 60000;

}  // namespace sinew::firmware
