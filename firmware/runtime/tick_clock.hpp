// Fixed-rate ticks on absolute deadlines (CLOCK_MONOTONIC, clock_nanosleep
// with TIMER_ABSTIME), so lateness never accumulates into drift. A late tick
// is counted as a deadline miss; when more than one whole period was lost the
// schedule skips ahead instead of bursting to catch up.
#pragma once

#include <cstdint>

#include "hal/common/monotonic_clock.hpp"

namespace sinew::firmware {

using hal::monotonic_ns;

class TickClock {
 public:
  TickClock(uint64_t period_ns, uint64_t start_ns) : period_(period_ns), next_(start_ns) {}
  // Sleeps until the next deadline; returns the nominal start time of the tick.
  uint64_t wait_next();
  // True if the step that just ran finished after the following deadline.
  bool finished_late(uint64_t now_ns) const { return now_ns > next_; }
  uint64_t period_ns() const { return period_; }
  uint64_t skipped_ticks() const { return skipped_; }

 private:
  uint64_t period_;
  uint64_t next_;
  uint64_t skipped_ = 0;
};

}  // namespace sinew::firmware
