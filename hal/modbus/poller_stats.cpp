#include "poller_stats.hpp"

namespace sinew::hal::modbus {

PollerCounters PollerStats::snapshot() const {
  PollerCounters c;
  c.cycles = cycles.load(kRelaxed);
  c.requests = requests.load(kRelaxed);
  c.responses = responses.load(kRelaxed);
  c.exceptions = exceptions.load(kRelaxed);
  for (size_t i = 0; i < by_exception.size(); ++i) c.by_exception[i] = by_exception[i].load(kRelaxed);
  c.timeouts = timeouts.load(kRelaxed);
  c.bad_responses = bad_responses.load(kRelaxed);
  c.link_errors = link_errors.load(kRelaxed);
  c.connects = connects.load(kRelaxed);
  c.connect_failures = connect_failures.load(kRelaxed);
  c.out_of_range = out_of_range.load(kRelaxed);
  c.backoff_ns = backoff_ns.load(kRelaxed);
  c.state = state();
  return c;
}

std::string format_counters(const PollerCounters& c) {
  std::string s = std::to_string(c.cycles) + " cycles, " + std::to_string(c.responses) + "/" +
                  std::to_string(c.requests) + " requests answered";
  s += ", exceptions " + std::to_string(c.exceptions);
  if (c.exceptions > 0) {
    std::string detail;
    for (size_t code = 1; code < c.by_exception.size(); ++code) {
      if (c.by_exception[code] == 0) continue;
      if (!detail.empty()) detail += ", ";
      detail += std::string(exception_name(static_cast<uint8_t>(code))) + " " + std::to_string(c.by_exception[code]);
    }
    s += " (" + detail + ")";
  }
  s += ", timeouts " + std::to_string(c.timeouts) + ", bad responses " + std::to_string(c.bad_responses) +
       ", out of range " + std::to_string(c.out_of_range) + ", connects " + std::to_string(c.connects) + " (failed " +
       std::to_string(c.connect_failures) + "), link errors " + std::to_string(c.link_errors);
  if (c.backoff_ns > 0) s += ", back-off " + std::to_string(c.backoff_ns / 1'000'000) + " ms";
  return s;
}

}  // namespace sinew::hal::modbus
