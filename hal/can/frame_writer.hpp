// The sending side of a CAN transport, as FrameSource is the receiving
// side: SocketCanWriter puts frames on a kernel interface, its simulated
// twin CandumpFrameWriter writes them to a candump log (candump_format.hpp).
// Called from one thread; send() never blocks and never allocates.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "can_frame.hpp"

namespace sinew::hal::can {

class FrameWriter {
 public:
  virtual ~FrameWriter() = default;
  virtual const char* name() const = 0;
  // Sends the frames in order at now_ns (CLOCK_MONOTONIC) and returns how
  // many went out; the rest are dropped and counted (a full transmit queue,
  // an interface that is down). A frame is never sent in part.
  virtual size_t send(std::span<const CanFrame> frames, uint64_t now_ns) = 0;
  virtual void flush() {}
  virtual uint64_t frames_sent() const = 0;
  virtual uint64_t frames_dropped() const = 0;
  // One line for the periodic report (may allocate: not per tick).
  virtual std::string status_line() const = 0;
};

}  // namespace sinew::hal::can
