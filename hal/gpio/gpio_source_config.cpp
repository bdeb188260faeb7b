#include "gpio_source_config.hpp"

#include <map>
#include <set>

namespace sinew::hal::gpio {

namespace {

constexpr uint64_t kMaxWindowNs = 1'000'000;
constexpr uint64_t kMaxDebounceNs = 1'000'000'000;
constexpr uint32_t kMaxCountsPerTurn = 1u << 30;

// Records the use of `line` by `who`; false with a message if taken or out of range.
bool claim(std::map<uint32_t, std::string>& used, int64_t line, uint32_t line_count, const std::string& who,
           std::string* error) {
  if (line < 0) return *error = who + " line must be >= 0", false;
  if (line_count != 0 && line >= line_count)
    return *error =
               who + " line " + std::to_string(line) + " is beyond the chip's " + std::to_string(line_count) + " lines",
           false;
  const auto [it, fresh] = used.emplace(static_cast<uint32_t>(line), who);
  if (!fresh) return *error = who + " line " + std::to_string(line) + " is already used by " + it->second, false;
  return true;
}

}  // namespace

bool validate(const GpioSourceConfig& config, uint32_t line_count, std::string* error) {
  const std::string prefix = "gpio source '" + config.name + "': ";
  std::string why;
  if (config.chip.empty()) return *error = prefix + "chip is empty", false;
  if (config.consumer.empty() || config.consumer.size() > 31)
    return *error = prefix + "consumer must be 1..31 characters", false;
  if (config.event_capacity < 16 || config.event_capacity > 65536)
    return *error = prefix + "event_capacity must be 16..65536", false;
  if (config.encoders.empty() && config.limits.empty() && config.sync.line == kNoLine && config.fault.line == kNoLine)
    return *error = prefix + "no encoders, limits, sync or fault line configured", false;

  std::map<uint32_t, std::string> used;
  std::set<uint16_t> inputs;
  for (size_t i = 0; i < config.encoders.size(); ++i) {
    const EncoderConfig& e = config.encoders[i];
    const std::string who = "encoder " + std::to_string(i);
    if (e.counts_per_turn < 1 || e.counts_per_turn > kMaxCountsPerTurn)
      return *error = prefix + who + ": counts_per_turn must be 1..2^30", false;
    if (e.window_ns > kMaxWindowNs) return *error = prefix + who + ": window_ns must be at most 1 ms", false;
    if (!claim(used, e.line_a, line_count, who + " A", &why) || !claim(used, e.line_b, line_count, who + " B", &why))
      return *error = prefix + why, false;
    if (e.line_index != kNoLine && !claim(used, e.line_index, line_count, who + " index", &why))
      return *error = prefix + why, false;
    if (!inputs.insert(e.input).second)
      return *error = prefix + who + ": input " + std::to_string(e.input) + " is fed by two encoders", false;
  }
  std::set<std::pair<uint16_t, LimitSide>> sides;
  for (size_t i = 0; i < config.limits.size(); ++i) {
    const LimitSwitchConfig& l = config.limits[i];
    const std::string who = "limit " + std::to_string(i);
    if (l.debounce_ns > kMaxDebounceNs) return *error = prefix + who + ": debounce_ns must be at most 1 s", false;
    if (!claim(used, l.line, line_count, who, &why)) return *error = prefix + why, false;
    if (!sides.insert({l.input, l.side}).second)
      return *error = prefix + who + ": input " + std::to_string(l.input) + " already has a " +
                      (l.side == LimitSide::kMin ? "min" : "max") + " limit switch",
             false;
  }
  if (config.sync.line != kNoLine && !claim(used, config.sync.line, line_count, "sync", &why))
    return *error = prefix + why, false;
  if (config.fault.line != kNoLine && !claim(used, config.fault.line, line_count, "fault", &why))
    return *error = prefix + why, false;
  return true;
}

}  // namespace sinew::hal::gpio
