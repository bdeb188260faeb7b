#include "input_health.hpp"

namespace sinew::hal {

void InputHealth::init(std::span<const InputLimits> limits, std::span<const int32_t> initial, uint64_t start_ns) {
  limits_.assign(limits.begin(), limits.end());
  values_.assign(limits.size(), 0);
  for (size_t i = 0; i < values_.size() && i < initial.size(); ++i) values_[i] = initial[i];
  status_.assign(limits.size(), kJointOk);
  last_valid_ns_.assign(limits.size(), start_ns);  // the timeout runs from start
  counters_.assign(limits.size(), InputCounters{});
  unassigned_ = {};
}

void InputHealth::begin_tick() {
  for (uint8_t& s : status_) s = static_cast<uint8_t>(s & ~kJointRejected);
}

void InputHealth::reject(int input, RejectReason reason) {
  const auto r = static_cast<size_t>(reason);
  if (input < 0 || static_cast<size_t>(input) >= values_.size()) {
    ++unassigned_.rejected[r];
    return;
  }
  ++counters_[static_cast<size_t>(input)].rejected[r];
  status_[static_cast<size_t>(input)] |= kJointRejected;
}

void InputHealth::apply(std::span<const JointSample> samples) {
  for (const JointSample& s : samples) {
    if (s.input >= values_.size()) {
      ++unassigned_.rejected[static_cast<size_t>(RejectReason::kUnknownId)];
      continue;
    }
    const InputLimits& lim = limits_[s.input];
    if (s.value < lim.min || s.value > lim.max || (s.status & hal::kSampleSenderFault) != 0) {
      reject(s.input, RejectReason::kOutOfRange);
      continue;
    }
    values_[s.input] = s.value;
    last_valid_ns_[s.input] = s.timestamp_ns;
    ++counters_[s.input].accepted;
  }
}

void InputHealth::end_tick(uint64_t now_ns) {
  for (size_t i = 0; i < values_.size(); ++i) {
    const uint64_t timeout = limits_[i].timeout_ns;
    const bool stale = timeout != 0 && now_ns > last_valid_ns_[i] && now_ns - last_valid_ns_[i] > timeout;
    const bool was = (status_[i] & kJointStale) != 0;
    if (stale && !was) ++counters_[i].stale_events;
    status_[i] = static_cast<uint8_t>(stale ? (status_[i] | kJointStale) : (status_[i] & ~kJointStale));
  }
}

size_t InputHealth::stale_count() const {
  size_t n = 0;
  for (uint8_t s : status_) n += (s & kJointStale) != 0 ? 1 : 0;
  return n;
}

}  // namespace sinew::hal
