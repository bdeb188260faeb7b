// The runtime's view of an output: the frame log and UDP writers
// (hal/output) implement it directly; the daemon wraps any of them in its
// I/O-thread queue (firmware/runtime/async_sink.hpp), itself an OutputSink.
// write() is called once per tick from one thread and must not allocate or
// block.
#pragma once

#include <cstdint>
#include <string>

#include "pose_frame.hpp"

namespace sinew::hal {

class OutputSink {
 public:
  virtual ~OutputSink() = default;
  // The sink's name in reports: the configuration's name for it.
  virtual const char* name() const = 0;
  // Returns false if the frame was dropped (counted by the sink); never blocks the tick.
  virtual bool write(const PoseFrame& frame) = 0;
  virtual void flush() = 0;
  // One human-readable line for the periodic report (may allocate: not per tick).
  virtual std::string status_line() const = 0;
  // Ends the sink at shutdown: writes what it still holds (a queue), then
  // flushes. Called once, from the thread that calls write().
  virtual void close() { flush(); }
  // Frames lost after write() had accepted them (a queued sink whose
  // underlying write later failed); counted besides write()'s false returns.
  virtual uint64_t frames_lost_after_write() const { return 0; }
};

}  // namespace sinew::hal
