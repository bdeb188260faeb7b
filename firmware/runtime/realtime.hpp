// Real-time setup for the tick thread, each step applied only when permitted
// and reported either way: SCHED_FIFO priority, CPU affinity, mlockall.
#pragma once

#include <string>

namespace sinew::firmware {

struct RealtimeOptions {
  int fifo_priority = 0;  // 1..99 for SCHED_FIFO; 0 keeps the default policy
  int cpu = -1;           // pin the calling thread to this CPU; -1 = no affinity
  bool lock_memory = false;
};

// Applies the options to the calling thread/process. Returns one line per
// option saying what took effect (e.g. "SCHED_FIFO 80: not permitted (EPERM)").
std::string apply_realtime(const RealtimeOptions& options);

}  // namespace sinew::firmware
