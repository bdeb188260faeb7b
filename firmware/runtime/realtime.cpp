#include "realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace sinew::firmware {

std::string apply_thread_realtime(pthread_t thread, int fifo_priority, int cpu, const std::string& label) {
  std::string report;
  const std::string prefix = label.empty() ? "" : label + ": ";
  if (fifo_priority > 0) {
    sched_param p{};
    p.sched_priority = fifo_priority;
    const int rc = pthread_setschedparam(thread, SCHED_FIFO, &p);
    report += prefix + "SCHED_FIFO " + std::to_string(fifo_priority) + ": " +
              (rc == 0 ? "on" : std::string("not applied (") + std::strerror(rc) + ")") + "\n";
  }
  if (cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(static_cast<size_t>(cpu), &set);
    const int rc = pthread_setaffinity_np(thread, sizeof(set), &set);
    report += prefix + "affinity cpu " + std::to_string(cpu) + ": " +
              (rc == 0 ? "on" : std::string("not applied (") + std::strerror(rc) + ")") + "\n";
  }
  return report;
}

int resolved_workers(int workers) {
  if (workers > 0) return workers;
  cpu_set_t set;
  CPU_ZERO(&set);
  const int cpus = sched_getaffinity(0, sizeof(set), &set) == 0 ? CPU_COUNT(&set) : 1;
  // One CPU stays with the sources' and sinks' I/O threads: on this
  // project's 2-core CI machine a second worker slowed the daemon's tick
  // (docs/performance.md, "Workers").
  return std::clamp(cpus - 1, 1, 4);
}

std::string apply_realtime(const RealtimeOptions& o) {
  std::string report = apply_thread_realtime(pthread_self(), o.fifo_priority, o.cpu, "");
  if (o.lock_memory) {
    const int rc = mlockall(MCL_CURRENT | MCL_FUTURE);
    report +=
        std::string("mlockall: ") + (rc == 0 ? "on" : std::string("not applied (") + std::strerror(errno) + ")") + "\n";
  }
  return report;
}

}  // namespace sinew::firmware
