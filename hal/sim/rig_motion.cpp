#include "hal/sim/rig_motion.hpp"

#include <algorithm>

#include "sim_core/fixed/trig.hpp"

namespace sinew::hal::sim {

RigMotion::RigMotion(std::vector<InputRange> ranges, uint32_t overshoot_per_1024)
    : ranges_(std::move(ranges)), overshoot_(overshoot_per_1024) {}

RigMotion RigMotion::keyframed(std::vector<InputRange> ranges, std::vector<uint64_t> times_ns,
                               std::vector<int32_t> values, std::vector<bool> has_track) {
  RigMotion m(std::move(ranges));
  m.key_times_ = std::move(times_ns);
  m.key_values_ = std::move(values);
  m.has_track_ = std::move(has_track);
  return m;
}

int32_t RigMotion::value(size_t input, uint64_t t_ns) const {
  if (key_times_.empty() || !has_track_[input]) return swing(input, t_ns);
  const size_t n = ranges_.size();
  if (t_ns <= key_times_.front()) return key_values_[input];
  if (t_ns >= key_times_.back()) return key_values_[(key_times_.size() - 1) * n + input];
  const size_t k =
      static_cast<size_t>(std::upper_bound(key_times_.begin(), key_times_.end(), t_ns) - key_times_.begin()) - 1;
  const int64_t a = key_values_[k * n + input], b = key_values_[(k + 1) * n + input];
  // In microseconds, and the product split, so that 64 bits hold it for keys
  // up to about 50 minutes apart: |delta % span| * into < span^2 < 2^63.
  const auto span = std::max<int64_t>(1, static_cast<int64_t>((key_times_[k + 1] - key_times_[k]) / 1000));
  const auto into = std::min(span, static_cast<int64_t>((t_ns - key_times_[k]) / 1000));
  const int64_t delta = b - a;
  const int64_t step = delta / span * into + (delta % span) * into / span;
  return static_cast<int32_t>(a + step);
}

int32_t RigMotion::swing(size_t input, uint64_t t_ns) const {
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

}  // namespace sinew::hal::sim
