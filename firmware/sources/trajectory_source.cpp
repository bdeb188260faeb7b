#include "trajectory_source.hpp"

#include "hal/sim/sweep.hpp"

namespace sinew::firmware {

TrajectorySource::TrajectorySource(std::vector<int32_t> min, std::vector<int32_t> max, uint64_t period_ns,
                                   uint64_t start_ns)
    : inputs_(static_cast<uint32_t>(min.size())), period_(period_ns), next_(start_ns + period_ns), start_(start_ns) {
  constexpr int64_t kOvershoot = (int64_t{1} << 32) / 72;  // 5 degrees
  for (size_t i = 0; i < min.size(); ++i) {
    centre_.push_back(static_cast<int32_t>((int64_t{min[i]} + max[i]) / 2));
    half_span_.push_back(static_cast<int32_t>((int64_t{max[i]} - min[i]) / 2 + kOvershoot));
  }
}

int32_t TrajectorySource::value(uint32_t input, uint32_t k) const {
  // The shared sweep spans +-2^30 (a third of a turn): rescale to the joint's range.
  const int64_t unit = hal::sim::sweep_input(input, k);
  return static_cast<int32_t>(centre_[input] + ((unit * half_span_[input]) >> 30));
}

size_t TrajectorySource::latch(uint64_t until_ns, std::span<hal::JointSample> out, InputHealth&) {
  size_t n = 0;
  while (next_ <= until_ns && n + inputs_ <= out.size()) {
    const auto step = static_cast<uint32_t>((next_ - start_) / period_);
    for (uint32_t i = 0; i < inputs_; ++i) out[n++] = {static_cast<uint16_t>(i), value(i, step), next_, hal::kSampleOk};
    next_ += period_;
    ++sent_;
  }
  return n;
}

std::string TrajectorySource::status_line() const { return "trajectory: " + std::to_string(sent_) + " sample sets"; }

}  // namespace sinew::firmware
