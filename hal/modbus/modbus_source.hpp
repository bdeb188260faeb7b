// The tick's view of a Modbus device: an InputSource whose latch() only
// takes the poller's latest snapshot (one atomic exchange) and copies out what
// is new since the previous latch. It never blocks, never allocates, and
// never touches libmodbus; all I/O runs on the poller thread.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "hal/common/input_source.hpp"
#include "poller.hpp"

namespace sinew::hal::modbus {

class ModbusSource : public InputSource {
 public:
  // Validates `config`, creates the libmodbus context and starts polling.
  // Null with a message naming the offending key on error.
  static std::unique_ptr<ModbusSource> create(PollerConfig config, std::string* error);
  ~ModbusSource() override;

  const char* name() const override { return poller_.config().name.c_str(); }
  // New accepted readings (timestamp <= until_ns) become samples; readings
  // rejected for range are reported as kOutOfRange and exception responses
  // as kMalformed, once each, for the channel's input.
  size_t latch(uint64_t until_ns, std::span<hal::JointSample> out, InputHealth& health) override;
  // ok: every request answered with data in the last cycle; degraded: some
  // were not (exceptions, timeouts); down: not connected or nothing answered.
  SourceState state() const override { return poller_.stats().state(); }
  std::string status_line() const override;

  // Any thread.
  PollerCounters counters() const { return poller_.stats().snapshot(); }
  const PollerConfig& config() const { return poller_.config(); }
  size_t request_count() const { return poller_.plan().size(); }
  // Tick thread only: channel `index` (configuration order) as of the last latch().
  const ChannelSlot& channel(size_t index) const { return poller_.exchange().front().channels[index]; }

 private:
  explicit ModbusSource(PollerConfig config);

  // Cumulative counters already handed to the tick, per channel.
  struct Latched {
    uint64_t samples = 0;
    uint64_t out_of_range = 0;
    uint64_t exceptions = 0;
  };

  Poller poller_;
  std::vector<Latched> latched_;
};

}  // namespace sinew::hal::modbus
