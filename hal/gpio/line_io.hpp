// The small line-event interface every GPIO backend implements: requested
// input lines deliver edge events with kernel timestamps, drained without
// blocking; one output line is driven. Kept this narrow so a libgpiod v2
// backend (one request fd for many lines, edge events with sequence numbers)
// can sit beside the v1 one (libgpiod_chip.hpp) and the simulated twin
// (simulated_gpio_chip.hpp) without the decoders noticing.
//
// Levels are physical (1 = high on the wire); active-low handling belongs to
// the caller, so the same logic runs on every backend.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace sinew::hal::gpio {

enum class Edge : uint8_t { kRising, kFalling };

struct LineEvent {
  uint32_t offset = 0;  // line offset on the chip
  Edge edge = Edge::kRising;
  uint64_t timestamp_ns = 0;  // kernel timestamp, CLOCK_MONOTONIC
};

enum class WaitResult : uint8_t { kReady, kTimeout, kError };

// A set of input lines requested together for both-edge events.
class LineGroup {
 public:
  virtual ~LineGroup() = default;
  // Moves pending events into `out`, oldest first by timestamp across the
  // group's lines (at most out.size(); the rest stay queued). Never blocks,
  // never allocates. Returns -1 on a read error (errno-like code in
  // last_error()), else the number of events.
  virtual int read_events(std::span<LineEvent> out) = 0;
  // Blocks up to timeout_ns until an event is pending (kReady) on any line
  // of the group. timeout_ns = 0 polls.
  virtual WaitResult wait(uint64_t timeout_ns) = 0;
  // Current physical levels, one per requested line, in request order.
  virtual bool get_levels(std::span<uint8_t> out) = 0;
  virtual int last_error() const = 0;
  // Reads that found a line's kernel FIFO full (events may have been lost
  // since: the v1 ABI drops new events silently). Cumulative.
  virtual uint64_t possible_overflows() const = 0;
};

// One requested output line.
class OutputLine {
 public:
  virtual ~OutputLine() = default;
  virtual bool set_level(bool high) = 0;  // physical level
};

class GpioChip {
 public:
  virtual ~GpioChip() = default;
  virtual const char* name() const = 0;
  virtual uint32_t line_count() const = 0;
  // Configuration time (may allocate). Null with a message on failure
  // (offset out of range, line busy, no event support).
  virtual std::unique_ptr<LineGroup> request_inputs(std::span<const uint32_t> offsets, std::string* error) = 0;
  virtual std::unique_ptr<OutputLine> request_output(uint32_t offset, bool initial_high, std::string* error) = 0;
};

}  // namespace sinew::hal::gpio
