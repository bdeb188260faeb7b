// [status] modbus_port end to end: a live sinewd serves its health as Modbus
// TCP registers (docs/modbus.md, "Status registers"), read by libmodbus's
// client while the daemon runs. Load-proof (docs/testing.md): the daemon runs
// until the test stops it, and every wait is a poll with a liveness bound
// that success ends at once; the test asserts only what holds at any
// scheduling (the layout, the counts, a tick that advances, the stale bit of
// the one input nothing feeds), never how many ticks ran.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <modbus.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "hal/common/pose_frame.hpp"
#include "hal/modbus/status_registers.hpp"
#include "tests/integration/daemon_harness.hpp"

namespace {

namespace r = sinew::hal::modbus::status_reg;
using Clock = std::chrono::steady_clock;

constexpr auto kLiveness = std::chrono::seconds(60);  // success returns at once

// The port the daemon printed ("status registers on Modbus TCP ADDR:PORT"), or 0.
int printed_port(const std::string& out) {
  const std::string key = "status registers on Modbus TCP 127.0.0.1:";
  const size_t at = out.find(key);
  return at == std::string::npos ? 0 : std::atoi(out.c_str() + at + key.size());
}

uint64_t tick_of(const std::vector<uint16_t>& regs) {
  uint64_t t = 0;
  for (int i = 0; i < 4; ++i) t = (t << 16) | regs[r::kTick + static_cast<size_t>(i)];
  return t;
}

}  // namespace

TEST(StatusRegisters, ALiveDaemonServesItsHealthOverModbus) {
  const std::string dir = testing::TempDir();
  const std::string config = dir + "/status.toml", out = dir + "/status.out";
  std::ofstream(config) << "[rig]\nbuiltin = \"hand\"\n[loop]\nrate_hz = 20\nstats_interval_s = 0\nmode = \"live\"\n"
                        << "[status]\nmodbus_port = 0\n"
                        << "[[source]]\ntype = \"trajectory\"\nperiod_ms = 50\n";
  std::remove(out.c_str());
  sinew::test::BackgroundDaemon daemon(config, out);
  ASSERT_TRUE(daemon.started());
  int port = 0;
  for (const auto until = Clock::now() + kLiveness; port == 0 && daemon.running() && Clock::now() < until;) {
    port = printed_port(sinew::test::slurp(out));
    if (port == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_GT(port, 0) << sinew::test::slurp(out);

  modbus_t* ctx = modbus_new_tcp("127.0.0.1", port);
  ASSERT_NE(ctx, nullptr);
  modbus_set_response_timeout(ctx, 10, 0);
  ASSERT_EQ(modbus_connect(ctx), 0);
  constexpr size_t kHandInputs = 23, kExternalForce = 22;  // 22 rig DOFs, then index_pip.force
  std::vector<uint16_t> regs(r::kInputStatus + kHandInputs);
  const auto read = [&] {
    return modbus_read_registers(ctx, 0, static_cast<int>(regs.size()), regs.data()) == static_cast<int>(regs.size());
  };
  // The first tick published, then a later one: the registers follow the run.
  uint64_t first = 0;
  for (const auto until = Clock::now() + kLiveness; Clock::now() < until;
       std::this_thread::sleep_for(std::chrono::milliseconds(20))) {
    ASSERT_TRUE(read()) << modbus_strerror(errno);
    if (regs[r::kHeartbeat] != 0) break;
  }
  ASSERT_NE(regs[r::kHeartbeat], 0u) << "no tick published";
  first = tick_of(regs);
  EXPECT_EQ(regs[r::kLayoutVersion], sinew::hal::modbus::kStatusLayout);
  EXPECT_EQ(regs[r::kInputCount], kHandInputs);
  EXPECT_EQ(regs[r::kSourceCount], 1u);
  EXPECT_EQ(regs[r::kSourcesDown], 0u);
  // The trajectory feeds every DOF but not the external force: once its
  // timeout has passed, that input alone is stale.
  bool stale_seen = false;
  for (const auto until = Clock::now() + kLiveness; Clock::now() < until;
       std::this_thread::sleep_for(std::chrono::milliseconds(20))) {
    ASSERT_TRUE(read()) << modbus_strerror(errno);
    stale_seen = (regs[r::kInputStatus + kExternalForce] & sinew::hal::kJointStale) != 0;
    if (stale_seen && tick_of(regs) > first) break;
  }
  EXPECT_TRUE(stale_seen);
  EXPECT_GT(tick_of(regs), first);
  EXPECT_EQ(regs[r::kStaleCount], 1u);
  for (size_t i = 0; i < kExternalForce; ++i)
    EXPECT_EQ(regs[r::kInputStatus + i] & sinew::hal::kJointStale, 0u) << "input " << i;
  // Nothing can be written.
  EXPECT_EQ(modbus_write_register(ctx, r::kTick, 7), -1);
  modbus_close(ctx);
  modbus_free(ctx);

  const int status = daemon.stop();
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << sinew::test::slurp(out);
  EXPECT_NE(sinew::test::slurp(out).find("reads served"), std::string::npos) << sinew::test::slurp(out);
}

TEST(StatusRegisters, APortInUseIsRefusedAtStartUp) {
  const std::string dir = testing::TempDir();
  const std::string config = dir + "/status_busy.toml";
  // Two daemons on one fixed port: whichever binds second is refused. The
  // first is held by a server of this test instead, so no timing matters.
  modbus_t* holder = modbus_new_tcp("127.0.0.1", 0);
  ASSERT_NE(holder, nullptr);
  const int listen_fd = modbus_tcp_listen(holder, 1);
  ASSERT_GE(listen_fd, 0);
  sockaddr_in addr{};
  socklen_t len = sizeof(addr);
  ASSERT_EQ(getsockname(listen_fd, reinterpret_cast<sockaddr*>(&addr), &len), 0);
  const int port = ntohs(addr.sin_port);
  std::ofstream(config) << "[rig]\nbuiltin = \"hand\"\n[loop]\nrate_hz = 20\nduration_s = 0.1\nmode = \"offline\"\n"
                        << "[status]\nmodbus_port = " << port << "\n"
                        << "[[source]]\ntype = \"trajectory\"\nperiod_ms = 50\n";
  const sinew::test::DaemonRun run = sinew::test::run_sinewd(config, dir + "/status_busy.out");
  EXPECT_NE(run.status, 0);
  EXPECT_NE(run.out.find("[status] modbus_port " + std::to_string(port)), std::string::npos) << run.out;
  ::close(listen_fd);
  modbus_free(holder);
}
