// The simulated rig's motion: every input swings sinusoidally across its
// joint range and a little past both limits (so clamping and the range check
// are exercised), each input at its own frequency so poses never repeat
// trivially. Integer math (sim_core's sin in Q2.30): identical everywhere.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sinew::hal::sim {

struct InputRange {
  int32_t min = 0;  // engine units: binary angle (rotation) or Q12.20 (translation)
  int32_t max = 0;
};

class RigMotion {
 public:
  // overshoot: how far past each limit the swing goes, as a fraction of the
  // half-range in 1/1024 (e.g. 51 is about 5 %).
  explicit RigMotion(std::vector<InputRange> ranges, uint32_t overshoot_per_1024 = 51);
  // A recorded motion instead of the swing: keyframe k at times_ns[k] gives
  // every input's value (values[k * inputs + i], engine units); linear in
  // between, held before the first and after the last; a track's column may
  // be absent (has_track[i] false): that input keeps the swing.
  static RigMotion keyframed(std::vector<InputRange> ranges, std::vector<uint64_t> times_ns,
                             std::vector<int32_t> values, std::vector<bool> has_track);
  size_t input_count() const { return ranges_.size(); }
  // Value of `input` at t_ns after the motion's start.
  int32_t value(size_t input, uint64_t t_ns) const;
  const InputRange& range(size_t input) const { return ranges_[input]; }

 private:
  int32_t swing(size_t input, uint64_t t_ns) const;

  std::vector<InputRange> ranges_;
  uint32_t overshoot_;
  std::vector<uint64_t> key_times_;  // empty: the swing
  std::vector<int32_t> key_values_;
  std::vector<bool> has_track_;
};

}  // namespace sinew::hal::sim
