#include "service_notify.hpp"

#include <cstdlib>

#if defined(SINEW_HAVE_SYSTEMD)
#include <systemd/sd-daemon.h>
#endif

namespace sinew::firmware {

#if defined(SINEW_HAVE_SYSTEMD)

bool service_notify_built() { return true; }

ServiceNotifier::ServiceNotifier() {
  active_ = std::getenv("NOTIFY_SOCKET") != nullptr;
  uint64_t usec = 0;
  // > 0 only when WatchdogSec= is set and WATCHDOG_PID is this process.
  if (active_ && sd_watchdog_enabled(0, &usec) > 0) watchdog_ns_ = usec * 1000u;
}

void ServiceNotifier::ready(const std::string& status) {
  if (active_) sd_notifyf(0, "READY=1\nSTATUS=%s", status.c_str());
}

void ServiceNotifier::status(const std::string& line) {
  if (active_) sd_notifyf(0, "STATUS=%s", line.c_str());
}

void ServiceNotifier::kick(uint64_t now_ns) {
  last_kick_ns_ = now_ns;
  sd_notify(0, "WATCHDOG=1");
}

void ServiceNotifier::stopping() {
  if (active_) sd_notify(0, "STOPPING=1");
}

#else

bool service_notify_built() { return false; }
ServiceNotifier::ServiceNotifier() = default;
void ServiceNotifier::ready(const std::string&) {}
void ServiceNotifier::status(const std::string&) {}
void ServiceNotifier::kick(uint64_t now_ns) { last_kick_ns_ = now_ns; }
void ServiceNotifier::stopping() {}

#endif

}  // namespace sinew::firmware
