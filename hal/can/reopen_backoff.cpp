#include "reopen_backoff.hpp"

namespace sinew::hal::can {

void ReopenBackoff::failed(uint64_t now_ns) {
  next_attempt_ns_ = now_ns + delay_ns_;
  delay_ns_ = delay_ns_ > policy_.max_ns / 2 ? policy_.max_ns : delay_ns_ * 2;
}

}  // namespace sinew::hal::can
