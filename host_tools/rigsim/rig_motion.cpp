#include "rig_motion.hpp"

#include "sim_core/fixed/trig.hpp"

namespace sinew::rigsim {

RigMotion::RigMotion(std::vector<InputRange> ranges, uint32_t overshoot_per_1024)
    : ranges_(std::move(ranges)), overshoot_(overshoot_per_1024) {}

int32_t RigMotion::value(size_t input, uint64_t t_ns) const {
  const InputRange& r = ranges_[input];
  const int64_t centre = (int64_t{r.min} + r.max) / 2;
  const int64_t half = (int64_t{r.max} - r.min) / 2;
  const int64_t amplitude = half + half * overshoot_ / 1024;
  // Input i completes a swing every (2 + 0.37 i) s: phase in binary angle.
  const uint64_t period_ms = 2000 + 370 * static_cast<uint64_t>(input);
  const uint64_t t_ms = t_ns / 1000000u;
  const auto phase = static_cast<fx::Angle>(((t_ms % period_ms) << 32) / period_ms);
  const int64_t s = fx::sin_unit(phase);  // Q2.30
  const int64_t v = centre + ((amplitude * s) >> 30);
  return static_cast<int32_t>(v < INT32_MIN ? INT32_MIN : (v > INT32_MAX ? INT32_MAX : v));
}

}  // namespace sinew::rigsim
