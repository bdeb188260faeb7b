#include "receive_timeouts.hpp"

#include <algorithm>

namespace sinew::hal::can {

namespace {
bool expired(uint64_t last_valid_ns, uint64_t timeout_ns, uint64_t now_ns) {
  return timeout_ns != 0 && now_ns > last_valid_ns && now_ns - last_valid_ns > timeout_ns;
}
}  // namespace

void ReceiveTimeouts::configure(std::span<const ChannelInfo> channels, uint64_t start_ns) {
  entries_.clear();
  size_t max_input = 0;
  for (const ChannelInfo& c : channels) {
    entries_.push_back({c.input, c.timeout_ns, start_ns, false});
    max_input = std::max<size_t>(max_input, c.input);
  }
  std::sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) { return a.input < b.input; });
  slot_of_.assign(entries_.empty() ? 0 : max_input + 1, -1);
  for (size_t i = 0; i < entries_.size(); ++i) slot_of_[entries_[i].input] = static_cast<int32_t>(i);
  stale_.assign(entries_.size(), 0);
  stale_events_ = 0;
}

void ReceiveTimeouts::on_sample(uint16_t input, uint64_t timestamp_ns) {
  if (input >= slot_of_.size() || slot_of_[input] < 0) return;
  Entry& e = entries_[static_cast<size_t>(slot_of_[input])];
  e.last_valid_ns = std::max(e.last_valid_ns, timestamp_ns);
}

std::span<const uint16_t> ReceiveTimeouts::stale_inputs(uint64_t now_ns) {
  size_t n = 0;
  for (Entry& e : entries_) {
    const bool stale = expired(e.last_valid_ns, e.timeout_ns, now_ns);
    if (stale && !e.stale) ++stale_events_;
    e.stale = stale;
    if (stale) stale_[n++] = e.input;
  }
  return {stale_.data(), n};
}

bool ReceiveTimeouts::is_stale(uint16_t input, uint64_t now_ns) const {
  if (input >= slot_of_.size() || slot_of_[input] < 0) return false;
  const Entry& e = entries_[static_cast<size_t>(slot_of_[input])];
  return expired(e.last_valid_ns, e.timeout_ns, now_ns);
}

}  // namespace sinew::hal::can
