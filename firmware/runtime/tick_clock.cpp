#include "tick_clock.hpp"

#include <cerrno>
#include <ctime>

namespace sinew::firmware {

uint64_t TickClock::wait_next() {
  const uint64_t now = monotonic_ns();
  if (now > next_ + period_) {  // over a whole period behind: skip, don't burst
    const uint64_t behind = (now - next_) / period_;
    skipped_ += behind;
    next_ += behind * period_;
  }
  const timespec deadline{static_cast<time_t>(next_ / 1000000000u), static_cast<long>(next_ % 1000000000u)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
  }
  const uint64_t tick = next_;
  next_ += period_;
  return tick;
}

}  // namespace sinew::firmware
