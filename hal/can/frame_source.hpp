// Where CAN frames come from: the SocketCAN backend or its simulated twin.
// One small interface so receivers and the firmware cannot tell them apart.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "bus_state.hpp"
#include "can_frame.hpp"
#include "frame_decoder.hpp"

namespace sinew::hal::can {

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual const char* name() const = 0;

  // Configuration time: accept only these identifiers (data and remote
  // frames; error frames always pass). Empty: accept everything.
  virtual bool set_filters(std::span<const FrameId> ids, std::string* error) = 0;

  // Moves the pending frames, oldest first, into `out` (at most out.size();
  // the rest wait for the next call). Error frames are delivered too, after
  // updating bus_state(). Timestamps are CLOCK_MONOTONIC nanoseconds. When
  // the source is down it is reopened here, with back-off, using now_ns
  // (CLOCK_MONOTONIC). Never blocks, never allocates.
  virtual size_t drain(std::span<CanFrame> out, uint64_t now_ns) = 0;

  virtual BusState bus_state() const = 0;
  virtual const BusCounters& counters() const = 0;
};

}  // namespace sinew::hal::can
