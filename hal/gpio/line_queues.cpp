#include "line_queues.hpp"

namespace sinew::hal::gpio {

void LineQueues::init(size_t lines, size_t capacity) {
  capacity_ = capacity;
  ring_.assign(lines * capacity, LineEvent{});
  head_.assign(lines, 0);
  count_.assign(lines, 0);
}

bool LineQueues::empty() const {
  for (size_t c : count_)
    if (c != 0) return false;
  return true;
}

bool LineQueues::push(size_t line, const LineEvent& event) {
  if (count_[line] == capacity_) return false;
  ring_[line * capacity_ + (head_[line] + count_[line]) % capacity_] = event;
  ++count_[line];
  return true;
}

size_t LineQueues::pop_oldest(std::span<LineEvent> out) {
  size_t n = 0;
  while (n < out.size()) {
    size_t best = count_.size();
    for (size_t i = 0; i < count_.size(); ++i) {
      if (count_[i] == 0) continue;
      if (best == count_.size() ||
          ring_[i * capacity_ + head_[i]].timestamp_ns < ring_[best * capacity_ + head_[best]].timestamp_ns)
        best = i;
    }
    if (best == count_.size()) break;
    out[n++] = ring_[best * capacity_ + head_[best]];
    head_[best] = (head_[best] + 1) % capacity_;
    --count_[best];
  }
  return n;
}

}  // namespace sinew::hal::gpio
