// sinewd under systemd's notification protocol (firmware/daemon/service_notify.*),
// with this test as the service manager: a datagram socket in NOTIFY_SOCKET
// and a watchdog in WATCHDOG_USEC. The daemon must say READY=1 first, then
// kick the watchdog only after completed ticks (at least once, never more
// often than every half interval), report its statistics as STATUS= and
// end with STOPPING=1. An offline run (every tick runs, none is skipped
// however loaded the machine) and a bound taken from the run's measured
// wall time: every assertion holds under any scheduling.
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/integration/daemon_harness.hpp"

namespace service_notify_e2e_test {

struct NotifySocket {
  int fd = -1;
  std::string path;
  explicit NotifySocket(const std::string& p) : path(p) {
    ::unlink(path.c_str());
    fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::strncpy(a.sun_path, path.c_str(), sizeof(a.sun_path) - 1);
    if (fd >= 0 && ::bind(fd, reinterpret_cast<const sockaddr*>(&a), sizeof(a)) != 0) {
      ::close(fd);
      fd = -1;
    }
  }
  ~NotifySocket() {
    if (fd >= 0) ::close(fd);
    ::unlink(path.c_str());
  }
  // Every datagram until `done` is set and the queue is empty, in order.
  // Read while the daemon runs, as systemd does: a unix datagram queue
  // holds net.unix.max_dgram_qlen (10) messages, and a full one blocks the
  // sender.
  std::vector<std::string> receive_until(const std::atomic<bool>& done) const {
    std::vector<std::string> out;
    char buf[4096];
    for (;;) {
      pollfd p{fd, POLLIN, 0};
      const bool finished = done.load();
      if (::poll(&p, 1, finished ? 0 : 50) > 0) {
        const ssize_t n = ::recv(fd, buf, sizeof(buf), MSG_DONTWAIT);
        if (n > 0) out.emplace_back(buf, static_cast<size_t>(n));
      } else if (finished) {
        return out;
      }
    }
  }
};

}  // namespace service_notify_e2e_test

TEST(ServiceNotify, ReadyThenWatchdogAfterTicksThenStopping) {
  const std::string dir = testing::TempDir();
  // sun_path holds 108 bytes: a short path in the temporary directory.
  service_notify_e2e_test::NotifySocket sock(dir + "/sinew-notify-" + std::to_string(::getpid()));
  ASSERT_GE(sock.fd, 0) << "cannot bind " << sock.path;
  const std::string config = dir + "/notify.toml";
  std::ofstream(config) << "[rig]\nbuiltin = \"arm\"\n[loop]\nrate_hz = 50\nduration_s = 1.0\nstats_interval_s = 0.2\n"
                        << "mode = \"offline\"\n[[source]]\ntype = \"trajectory\"\nperiod_ms = 20\n";
  constexpr uint64_t kWatchdogUs = 100000;
  ::setenv("NOTIFY_SOCKET", sock.path.c_str(), 1);
  ::setenv("WATCHDOG_USEC", std::to_string(kWatchdogUs).c_str(), 1);
  ::unsetenv("WATCHDOG_PID");
  std::atomic<bool> exited{false};
  std::vector<std::string> messages;
  std::thread manager([&] { messages = sock.receive_until(exited); });
  const auto started = std::chrono::steady_clock::now();
  const sinew::test::DaemonRun daemon = sinew::test::run_sinewd(config, dir + "/notify.out");
  const auto wall_us =
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - started).count();
  exited.store(true);
  manager.join();
  ::unsetenv("NOTIFY_SOCKET");
  ::unsetenv("WATCHDOG_USEC");
  ASSERT_EQ(daemon.status, 0) << daemon.command << "\n" << daemon.out;
  EXPECT_NE(daemon.out.find("systemd watchdog"), std::string::npos) << daemon.out;

  ASSERT_FALSE(messages.empty()) << "no notification arrived";
  EXPECT_NE(messages.front().find("READY=1"), std::string::npos) << messages.front();
  EXPECT_NE(messages.back().find("STOPPING=1"), std::string::npos) << messages.back();
  size_t kicks = 0, statuses = 0;
  for (const std::string& m : messages) {
    kicks += m == "WATCHDOG=1" ? 1 : 0;
    statuses += m.rfind("STATUS=stats tick", 0) == 0 ? 1 : 0;
  }
  // The 50 ticks complete, so the first kicks; after it, at most one per
  // half interval of the daemon's whole run (shorter than the wall time
  // measured around it).
  EXPECT_GE(kicks, 1u);
  EXPECT_LE(kicks, static_cast<size_t>(wall_us) / (kWatchdogUs / 2) + 1);
  EXPECT_GE(statuses, 1u) << "no statistics line reached STATUS=";
}
