#include "view_loop.hpp"

namespace sinew::view {

void PeriodEstimate::add(const hal::output::DecodedPose& pose) {
  if (have_ && pose.tick > last_tick_ && pose.timestamp_ns > last_ns_) {
    const uint64_t p = (pose.timestamp_ns - last_ns_) / (pose.tick - last_tick_);
    if (p > 0 && (best_ns_ == 0 || p < best_ns_)) best_ns_ = p;
  }
  have_ = true;
  last_tick_ = pose.tick;
  last_ns_ = pose.timestamp_ns;
}

uint64_t PeriodEstimate::period_ns(uint32_t tick_hz_override) const {
  if (tick_hz_override > 0) return 1000000000ull / tick_hz_override;
  return best_ns_ > 0 ? best_ns_ : 1000000;  // sinewd's default rate, 1 kHz, until two frames arrive
}

void mark_held_inputs(const hal::output::DecodedPose& pose, const hal::output::DecodedPose* previous,
                      std::vector<uint8_t>* held) {
  held->assign(pose.input_count, 0);
  if (previous == nullptr || previous->tick + 1 != pose.tick || previous->input_count != pose.input_count) return;
  for (uint32_t i = 0; i < pose.input_count; ++i) (*held)[i] = pose.input_value[i] == previous->input_value[i] ? 1 : 0;
}

}  // namespace sinew::view
