// The runtime's view of inputs and outputs: every backend (SocketCAN,
// Modbus, GPIO, replay, simulation) is an InputSource; every output (frame
// log, UDP, CAN) is an OutputSink. Per-tick calls must not allocate or block.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "input_health.hpp"
#include "pose_frame.hpp"

namespace sinew::hal {

enum class SourceState : uint8_t {
  kOk,        // delivering
  kDegraded,  // delivering with errors (e.g. CAN error-passive)
  kDown,      // not delivering; being retried with back-off (bus-off, socket error, disconnect)
};

const char* source_state_name(SourceState s);

class InputSource {
 public:
  virtual ~InputSource() = default;
  virtual const char* name() const = 0;
  // Latches what arrived with a timestamp <= until_ns: accepted samples into
  // `out` (returns how many), rejections reported to `health`. Never blocks.
  virtual size_t latch(uint64_t until_ns, std::span<JointSample> out, InputHealth& health) = 0;
  virtual SourceState state() const = 0;
  // One human-readable line for the periodic report (may allocate: not per tick).
  virtual std::string status_line() const = 0;
};

class OutputSink {
 public:
  virtual ~OutputSink() = default;
  virtual const char* name() const = 0;
  // Returns false if the frame was dropped (counted by the sink); never blocks the tick.
  virtual bool write(const PoseFrame& frame) = 0;
  virtual void flush() = 0;
  virtual std::string status_line() const = 0;
  // Ends the sink at shutdown: writes what it still holds (a queue), then
  // flushes. Called once, from the thread that calls write().
  virtual void close() { flush(); }
  // Frames lost after write() had accepted them (a queued sink whose
  // underlying write later failed); counted besides write()'s false returns.
  virtual uint64_t frames_lost_after_write() const { return 0; }
};

}  // namespace sinew::hal
