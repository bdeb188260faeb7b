// What the poller thread hands to the tick after every cycle: per channel the
// latest accepted value with its timestamp, and cumulative counters, so that
// the tick can tell what is new since it last looked even when it missed
// intermediate snapshots.
#pragma once

#include <cstdint>
#include <vector>

#include "hal/common/input_source.hpp"

namespace sinew::hal::modbus {

// Outcome of a channel's latest read.
enum class ChannelStatus : uint8_t {
  kNeverRead,
  kOk,          // value accepted
  kOutOfRange,  // value outside [min, max]: rejected, previous value held
  kException,   // the device answered its request with an exception (see last_exception)
  kNoResponse,  // timeout, malformed response or lost link
};

const char* channel_status_name(ChannelStatus s);

struct ChannelSlot {
  int32_t value = 0;           // latest accepted value, engine units
  uint64_t timestamp_ns = 0;   // when it was read (CLOCK_MONOTONIC, after the response arrived)
  uint64_t samples = 0;        // accepted readings so far: a new one is there when this grows
  uint64_t out_of_range = 0;   // readings rejected for range, cumulative
  uint64_t exceptions = 0;     // exception responses to this channel's request, cumulative
  uint64_t failed_reads = 0;   // timeouts, malformed responses, lost link, cumulative
  uint8_t last_exception = 0;  // code of the latest exception response (0: none so far)
  ChannelStatus status = ChannelStatus::kNeverRead;
};

struct PollSnapshot {
  uint64_t cycle = 0;                 // poll cycles completed
  std::vector<ChannelSlot> channels;  // in configuration order; sized once
};

}  // namespace sinew::hal::modbus
