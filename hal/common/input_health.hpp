// Per-input health: every rig input holds its last good value. A sample
// refreshes it; an input with no valid sample for longer than its timeout is
// held and flagged stale; rejected samples are counted and flagged for the
// tick. The engine keeps stepping on whatever is held. Allocation-free after
// init (arrays sized from the rig's input count).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "joint_sample.hpp"
#include "pose_frame.hpp"

namespace sinew::hal {

struct InputLimits {
  int32_t min = INT32_MIN;  // accepted range in engine units (binary angle / Len)
  int32_t max = INT32_MAX;
  uint64_t timeout_ns = 0;  // 0 = never stale
};

struct InputCounters {
  uint64_t accepted = 0;
  uint64_t rejected[static_cast<int>(RejectReason::kCount)] = {};
  uint64_t stale_events = 0;  // transitions into stale
};

class InputHealth {
 public:
  // initial: value each input holds before its first sample (e.g. rest pose 0).
  void init(std::span<const InputLimits> limits, std::span<const int32_t> initial, uint64_t start_ns);

  // Applies this tick's accepted samples (already CRC/counter-checked by the
  // backend; range-checked here). Samples for unknown inputs are counted.
  void apply(std::span<const JointSample> samples);
  // Records a rejection reported by a backend for `input` (or for no input).
  void reject(int input, RejectReason reason);
  // Ends the tick at `now_ns`: updates stale flags. Call once per tick, after apply.
  void end_tick(uint64_t now_ns);
  // Starts the next tick: clears the per-tick flags (rejected).
  void begin_tick();

  std::span<const int32_t> values() const { return values_; }
  std::span<const uint8_t> status() const { return status_; }
  const InputCounters& counters(size_t input) const { return counters_[input]; }
  const InputCounters& unassigned() const { return unassigned_; }
  size_t stale_count() const;

 private:
  std::vector<InputLimits> limits_;
  std::vector<int32_t> values_;
  std::vector<uint8_t> status_;
  std::vector<uint64_t> last_valid_ns_;
  std::vector<InputCounters> counters_;
  InputCounters unassigned_;
};

}  // namespace sinew::hal
