// The simulated rig's motion: every input swings sinusoidally across its
// joint range and a little past both limits (so clamping and the range check
// are exercised), each input at its own frequency so poses never repeat
// trivially. Integer math (sim_core's sin in Q2.30): identical everywhere.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sinew::rigsim {

struct InputRange {
  int32_t min = 0;  // engine units: binary angle (rotation) or Q12.20 (translation)
  int32_t max = 0;
};

class RigMotion {
 public:
  // overshoot: how far past each limit the swing goes, as a fraction of the
  // half-range in 1/1024 (e.g. 51 is about 5 %).
  explicit RigMotion(std::vector<InputRange> ranges, uint32_t overshoot_per_1024 = 51);
  size_t input_count() const { return ranges_.size(); }
  // Value of `input` at t_ns after the motion's start.
  int32_t value(size_t input, uint64_t t_ns) const;
  const InputRange& range(size_t input) const { return ranges_[input]; }

 private:
  std::vector<InputRange> ranges_;
  uint32_t overshoot_;
};

}  // namespace sinew::rigsim
