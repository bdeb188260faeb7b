// In-process twin of a GPIO chip, behind the same GpioChip interface as the
// libgpiod backend. The test or the simulated rig owns a SimulatedGpio (the
// "wire"), drives input levels with explicit timestamps, and reads output
// levels; the source owns a chip handle from chip(). Like the v1 kernel ABI,
// each requested input line has its own event FIFO of 16 events; when it is
// full, new events are dropped (counted).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "line_io.hpp"
#include "line_queues.hpp"

namespace sinew::hal::gpio {

class SimulatedGpio {
 public:
  explicit SimulatedGpio(uint32_t line_count = 32, size_t fifo_events = 16);
  ~SimulatedGpio();
  SimulatedGpio(const SimulatedGpio&) = delete;
  SimulatedGpio& operator=(const SimulatedGpio&) = delete;

  // A chip handle for a source (the wire must outlive it).
  std::unique_ptr<GpioChip> chip();

  // Drives an input to a physical level at ts; an edge event is queued when
  // the level changes and the line is requested for events.
  void set_level(uint32_t offset, bool high, uint64_t ts);
  // Queues an edge event whatever the current level (lost or doubled edges).
  void inject_edge(uint32_t offset, Edge edge, uint64_t ts);
  // Physical level of a line (an output as driven by the source, or an input).
  bool level(uint32_t offset) const { return levels_[offset] != 0; }
  bool requested(uint32_t offset) const { return owner_[offset] != nullptr || output_[offset] != 0; }
  // The next read on any group fails with this errno (0: reads succeed).
  void fail_reads(int err) { fail_errno_ = err; }
  uint64_t dropped_events() const { return dropped_; }
  uint32_t line_count() const { return static_cast<uint32_t>(levels_.size()); }

 private:
  friend class SimulatedChip;
  friend class SimulatedGroup;
  friend class SimulatedOutput;

  std::vector<uint8_t> levels_;
  std::vector<class SimulatedGroup*> owner_;  // group that requested each input line
  std::vector<uint8_t> output_;
  size_t fifo_events_;
  int fail_errno_ = 0;
  uint64_t dropped_ = 0;
};

}  // namespace sinew::hal::gpio
