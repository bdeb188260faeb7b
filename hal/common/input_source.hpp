// The runtime's view of an input: every backend (SocketCAN, Modbus, GPIO,
// candump replay, the simulated rig, the trajectory) is an InputSource; the
// outputs are OutputSinks (output_sink.hpp). Per-tick calls must not allocate
// or block.
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

// What an input-triggered loop may ask a source between ticks (docs/pipeline.md,
// "The daemon's tick"): what has arrived since its last latch, without consuming it.
enum ArrivalSignal : uint8_t {
  kSignalsNothing = 0,
  kSignalsComplete = 1u << 0,  // can tell when every input it feeds has a new sample
  kSignalsSync = 1u << 1,      // carries a sync event (a CAN SYNC frame, a GPIO sync edge)
};

struct Arrival {
  bool complete = false;  // every input it feeds has a new sample (or a rejected one) stamped <= now
  bool sync = false;      // a sync event stamped <= now
};

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
  // ArrivalSignal bits: which of arrival()'s answers mean something. A source
  // that signals nothing is sampled by whatever tick runs, as in periodic mode.
  virtual uint8_t arrival_signals() const { return kSignalsNothing; }
  // What arrived with a timestamp <= now_ns since the last latch(). Leaves
  // it for the next latch; never blocks, never allocates.
  virtual Arrival arrival(uint64_t now_ns) {
    (void)now_ns;
    return {};
  }
};

}  // namespace sinew::hal
