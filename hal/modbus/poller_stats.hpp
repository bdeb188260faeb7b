// Source-wide counters of the poller: written by the poller thread only,
// readable from any thread at any time (relaxed atomics: each counter is
// exact, a set of them is not one consistent instant).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <string>

#include "hal/common/input_source.hpp"
#include "read_outcome.hpp"

namespace sinew::hal::modbus {

// A plain copy of the counters, for reports and tests.
struct PollerCounters {
  uint64_t cycles = 0;                                   // poll cycles run (connected)
  uint64_t requests = 0;                                 // read requests sent
  uint64_t responses = 0;                                // requests answered with data
  uint64_t exceptions = 0;                               // requests answered with an exception
  std::array<uint64_t, kExceptionCodes> by_exception{};  // per exception code
  uint64_t timeouts = 0;
  uint64_t bad_responses = 0;
  uint64_t link_errors = 0;  // connection lost while polling
  uint64_t connects = 0;     // successful connects
  uint64_t connect_failures = 0;
  uint64_t out_of_range = 0;  // readings rejected for range
  uint64_t backoff_ns = 0;    // current back-off wait (0 while healthy)
  SourceState state = SourceState::kDown;
};

class PollerStats {
 public:
  // One writer: a load and a store, no read-modify-write needed.
  static void add(std::atomic<uint64_t>& c, uint64_t n = 1) { c.store(c.load(kRelaxed) + n, kRelaxed); }
  void set_state(SourceState s) { state_.store(s, kRelaxed); }
  SourceState state() const { return state_.load(kRelaxed); }
  PollerCounters snapshot() const;

  std::atomic<uint64_t> cycles{0}, requests{0}, responses{0}, exceptions{0}, timeouts{0}, bad_responses{0},
      link_errors{0}, connects{0}, connect_failures{0}, out_of_range{0}, backoff_ns{0};
  std::array<std::atomic<uint64_t>, kExceptionCodes> by_exception{};

 private:
  static constexpr std::memory_order kRelaxed = std::memory_order_relaxed;
  std::atomic<SourceState> state_{SourceState::kDown};
};

// "ok, 1234 cycles, 2468/2468 requests answered, exceptions 2 (illegal data address 2), ..."
std::string format_counters(const PollerCounters& c);

}  // namespace sinew::hal::modbus
