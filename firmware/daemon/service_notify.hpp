// systemd's service notification protocol (sd_notify(3), libsystemd) for
// sinewd run as a Type=notify service with a watchdog
// (firmware/systemd/sinewd.service, docs/service.md): READY=1 once the
// sources and sinks are open, STATUS= with the last statistics line,
// WATCHDOG=1 while ticks complete (a hung tick loop stops sending it and
// systemd kills and restarts the daemon), STOPPING=1 at shutdown. Does
// nothing when sinewd was not started by systemd (no NOTIFY_SOCKET) or was
// built without libsystemd (a board image without systemd).
#pragma once

#include <cstdint>
#include <string>

namespace sinew::firmware {

class ServiceNotifier {
 public:
  ServiceNotifier();
  // Whether a service manager listens (NOTIFY_SOCKET set, libsystemd built in).
  bool active() const { return active_; }
  // The watchdog interval systemd asked for (WatchdogSec=), 0 without one.
  uint64_t watchdog_interval_ns() const { return watchdog_ns_; }
  void ready(const std::string& status);
  void status(const std::string& line);
  // After each tick that completed: WATCHDOG=1 at most every half interval,
  // so the kick never lags the interval by more than one tick.
  void tick_completed(uint64_t now_ns) {
    if (watchdog_ns_ != 0 && now_ns - last_kick_ns_ >= watchdog_ns_ / 2) kick(now_ns);
  }
  void stopping();

 private:
  void kick(uint64_t now_ns);

  bool active_ = false;
  uint64_t watchdog_ns_ = 0;
  uint64_t last_kick_ns_ = 0;
};

// Whether this build can speak to systemd (built with libsystemd).
bool service_notify_built();

}  // namespace sinew::firmware
