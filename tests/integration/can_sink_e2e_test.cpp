// The CAN pose output end to end through the daemon binary: a [[sink]] of
// type "can" whose transport is the candump log (SocketCanWriter's simulated
// twin) writes, for every tick, one frame per input that carries exactly
// what the frame log of the same run carries: the applied value, the status
// bits and the tick's counter. Offline mode: no deadline, nothing dropped.
#include <gtest/gtest.h>
#include <linux/can.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "hal/can/candump_format.hpp"
#include "hal/output/can_frames.hpp"
#include "tests/integration/daemon_harness.hpp"

namespace {

// stem: this test's own file names (ctest runs the tests in parallel).
std::string can_config(const std::string& dir, const std::string& stem, const std::string& sink) {
  const std::string path = dir + "/" + stem + ".toml";
  std::ofstream(path) << "[rig]\nbuiltin = \"hand\"\n[loop]\nrate_hz = 50\nduration_s = 1.0\nstats_interval_s = 0\n"
                      << "mode = \"offline\"\n[[source]]\ntype = \"trajectory\"\nperiod_ms = 20\n"
                      << "[[sink]]\ntype = \"log\"\npath = \"" << dir << "/" << stem << ".log\"\n"
                      << "[[sink]]\ntype = \"can\"\n"
                      << sink;
  return path;
}

can_frame to_can_frame(const sinew::hal::can::CanFrame& f) {
  can_frame k{};
  k.can_id = f.id | (f.extended ? CAN_EFF_FLAG : 0u);
  k.len = f.len;
  for (uint8_t i = 0; i < f.len && i < CAN_MAX_DLEN; ++i) k.data[i] = f.data[i];
  return k;
}

}  // namespace

TEST(CanSink, EveryTickSendsEveryInputAsTheFrameLogHasIt) {
  const std::string dir = testing::TempDir();
  const std::string candump = dir + "/can_sink.candump";
  std::remove(candump.c_str());
  std::remove((dir + "/can_sink.log").c_str());  // a frame log is appended to, never replaced
  const sinew::test::DaemonRun daemon = sinew::test::run_sinewd(
      can_config(dir, "can_sink", "candump = \"" + candump + "\"\ninterface = \"vcan3\"\ncan_id = 0x123\n"),
      dir + "/can.out");
  ASSERT_EQ(daemon.status, 0) << daemon.command << "\n" << daemon.out;
  const sinew::test::FrameLog log = sinew::test::read_frame_log(dir + "/can_sink.log");
  ASSERT_EQ(log.poses.size(), 50u);
  sinew::hal::can::CandumpLog frames;
  std::string error;
  ASSERT_TRUE(sinew::hal::can::read_candump_file(candump, frames, &error)) << error;
  ASSERT_TRUE(frames.errors.empty()) << frames.errors[0].message;
  const size_t inputs = log.poses[0].input_value.size();
  ASSERT_GT(inputs, 0u);
  ASSERT_EQ(frames.frames.size(), log.poses.size() * inputs);
  size_t k = 0;
  for (const auto& pose : log.poses) {
    for (size_t i = 0; i < inputs; ++i, ++k) {
      const sinew::hal::can::LoggedFrame& logged = frames.frames[k];
      EXPECT_EQ(logged.interface, "vcan3");
      EXPECT_EQ(logged.frame.id, 0x123u);
      EXPECT_FALSE(logged.frame.extended);
      sinew::hal::output::CanJointFrame joint;
      ASSERT_TRUE(sinew::hal::output::decode_can_joint_frame(to_can_frame(logged.frame), &joint)) << "line " << k + 1;
      EXPECT_EQ(joint.input, i);
      EXPECT_EQ(joint.value, pose.input_value[i]) << "tick " << pose.tick << " input " << i;
      EXPECT_EQ(joint.status, pose.input_status[i]) << "tick " << pose.tick << " input " << i;
      EXPECT_EQ(joint.counter, pose.tick & 0x0F);
    }
    if (::testing::Test::HasFailure()) break;
  }
}

TEST(CanSink, RefusesAConfigurationItCannotSend) {
  const std::string dir = testing::TempDir();
  struct Case {
    std::string sink, message;
  } cases[] = {
      {"", "interface (a SocketCAN interface) or candump (a log path) is required"},
      {"candump = \"" + dir + "/x.candump\"\ncan_id = 0x800\n", "does not fit 11 bits"},
      {"interface = \"no-such-can9\"\n", "CAN interface no-such-can9"},
  };
  for (const Case& c : cases) {
    const sinew::test::DaemonRun daemon =
        sinew::test::run_sinewd(can_config(dir, "can_refused", c.sink), dir + "/can_refused.out");
    EXPECT_NE(daemon.status, 0) << c.sink;
    EXPECT_NE(daemon.out.find(c.message), std::string::npos) << c.sink << "\n" << daemon.out;
  }
}
