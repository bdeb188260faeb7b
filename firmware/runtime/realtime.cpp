#include "realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>

namespace sinew::firmware {

std::string apply_realtime(const RealtimeOptions& o) {
  std::string report;
  if (o.fifo_priority > 0) {
    sched_param p{};
    p.sched_priority = o.fifo_priority;
    const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &p);
    report += "SCHED_FIFO " + std::to_string(o.fifo_priority) + ": " + (rc == 0 ? "on" : std::string("not applied (") + std::strerror(rc) + ")") + "\n";
  }
  if (o.cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(static_cast<size_t>(o.cpu), &set);
    const int rc = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
    report += "affinity cpu " + std::to_string(o.cpu) + ": " + (rc == 0 ? "on" : std::string("not applied (") + std::strerror(rc) + ")") + "\n";
  }
  if (o.lock_memory) {
    const int rc = mlockall(MCL_CURRENT | MCL_FUTURE);
    report += std::string("mlockall: ") + (rc == 0 ? "on" : std::string("not applied (") + std::strerror(errno) + ")") + "\n";
  }
  return report;
}

}  // namespace sinew::firmware
