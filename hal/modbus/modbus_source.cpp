#include "modbus_source.hpp"

#include <utility>

namespace sinew::hal::modbus {

std::unique_ptr<ModbusSource> ModbusSource::create(PollerConfig config, std::string* error) {
  if (!validate(config, error)) return nullptr;
  std::unique_ptr<ModbusSource> source(new ModbusSource(std::move(config)));
  if (!source->poller_.start(error)) return nullptr;
  return source;
}

ModbusSource::ModbusSource(PollerConfig config)
    : poller_(std::move(config)), latched_(poller_.config().channels.size()) {}

ModbusSource::~ModbusSource() { poller_.stop(); }

size_t ModbusSource::latch(uint64_t until_ns, std::span<hal::JointSample> out, InputHealth& health) {
  TripleBuffer<PollSnapshot>& exchange = poller_.exchange();
  exchange.refresh();
  const PollSnapshot& snapshot = exchange.front();
  const std::vector<ChannelConfig>& channels = poller_.config().channels;
  size_t n = 0;
  for (size_t i = 0; i < channels.size(); ++i) {
    const ChannelSlot& slot = snapshot.channels[i];
    Latched& seen = latched_[i];
    const int input = channels[i].input;
    // Counters are cumulative, so nothing is lost when the tick skipped snapshots.
    for (; seen.out_of_range < slot.out_of_range; ++seen.out_of_range)
      health.reject(input, hal::RejectReason::kOutOfRange);
    for (; seen.exceptions < slot.exceptions; ++seen.exceptions) health.reject(input, hal::RejectReason::kMalformed);
    if (slot.samples == seen.samples || slot.timestamp_ns > until_ns || n == out.size()) continue;
    out[n++] = hal::JointSample{channels[i].input, slot.value, slot.timestamp_ns, hal::kSampleOk};
    seen.samples = slot.samples;
  }
  return n;
}

std::string ModbusSource::status_line() const {
  const PollerCounters c = counters();
  return std::string(source_state_name(c.state)) + ", " + std::to_string(request_count()) + " requests/cycle, " +
         format_counters(c);
}

}  // namespace sinew::hal::modbus
