// The CAN pose output end to end through the daemon binary, with the
// candump log (SocketCanWriter's simulated twin) as its transport. In the
// joint-stream protocol a second sinewd, replaying that log through its
// candump source, applies every input the first one applied; as compact
// joint frames every tick carries exactly what the frame log of the same
// run carries. Offline and replay modes: no deadline, nothing dropped.
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
      can_config(dir, "can_sink",
                 "protocol = \"joint-frames\"\ncandump = \"" + candump + "\"\ninterface = \"vcan3\"\ncan_id = 0x123\n"),
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

// Board A's applied inputs, sent in the joint-stream protocol, drive board
// B's rig: B replays A's CAN output through its candump source on the same
// tick schedule and applies, tick for tick, the values A applied. An input A
// holds stale (the hand's external force, which A's trajectory does not
// feed) reaches B with the sender-fault bit: B rejects those samples and
// holds it stale too, so a held value never passes for a measurement.
TEST(CanSink, ASecondDaemonFollowsTheFirstOverTheJointStream) {
  const std::string dir = testing::TempDir();
  const std::string bus = dir + "/joint_stream.candump", a_log = dir + "/board_a.log", b_log = dir + "/board_b.log";
  for (const std::string& f : {bus, a_log, b_log}) std::remove(f.c_str());
  const std::string loop = "[rig]\nbuiltin = \"hand\"\n[loop]\nrate_hz = 20\nduration_s = 2.0\nstats_interval_s = 0\n";
  const std::string a_config = dir + "/board_a.toml", b_config = dir + "/board_b.toml";
  std::ofstream(a_config) << loop << "mode = \"offline\"\n[[source]]\ntype = \"trajectory\"\nperiod_ms = 50\n"
                          << "[[sink]]\ntype = \"log\"\npath = \"" << a_log << "\"\n"
                          << "[[sink]]\ntype = \"can\"\ninterface = \"can0\"\ncandump = \"" << bus << "\"\n";
  std::ofstream(b_config) << loop << "mode = \"replay\"\n[[source]]\ntype = \"candump\"\nperiod_ms = 50\norigin_s = 0\n"
                          << "path = \"" << bus << "\"\n[[sink]]\ntype = \"log\"\npath = \"" << b_log << "\"\n";
  const sinew::test::DaemonRun a = sinew::test::run_sinewd(a_config, dir + "/board_a.out");
  ASSERT_EQ(a.status, 0) << a.command << "\n" << a.out;
  const sinew::test::DaemonRun b = sinew::test::run_sinewd(b_config, dir + "/board_b.out");
  ASSERT_EQ(b.status, 0) << b.command << "\n" << b.out;
  const sinew::test::FrameLog sent = sinew::test::read_frame_log(a_log), followed = sinew::test::read_frame_log(b_log);
  ASSERT_EQ(sent.poses.size(), 40u);
  ASSERT_EQ(followed.poses.size(), 40u);
  for (size_t k = 0; k < sent.poses.size(); ++k) {
    EXPECT_EQ(followed.poses[k].input_value, sent.poses[k].input_value) << "tick " << k;
    for (size_t i = 0; i < followed.poses[k].input_status.size(); ++i) {
      const uint8_t a_status = sent.poses[k].input_status[i];
      const uint8_t faulted = (a_status & sinew::hal::kJointStale) != 0 ? sinew::hal::kJointRejected : 0;
      EXPECT_EQ(followed.poses[k].input_status[i], a_status | faulted) << "tick " << k << " input " << i;
    }
    for (int c = 0; c < 3; ++c) EXPECT_EQ(followed.poses[k].position[c], sent.poses[k].position[c]) << "tick " << k;
    if (::testing::Test::HasFailure()) break;
  }
}

TEST(CanSink, RefusesAConfigurationItCannotSend) {
  const std::string dir = testing::TempDir();
  struct Case {
    std::string sink, message;
  } cases[] = {
      {"", "interface (a SocketCAN interface) or candump (a log path) is required"},
      {"protocol = \"joint-frames\"\ncandump = \"" + dir + "/x.candump\"\ncan_id = 0x800\n", "does not fit 11 bits"},
      {"protocol = \"j1939\"\ncandump = \"" + dir + "/x.candump\"\n", "protocol"},
      {"interface = \"no-such-can9\"\n", "CAN interface no-such-can9"},
  };
  for (const Case& c : cases) {
    const sinew::test::DaemonRun daemon =
        sinew::test::run_sinewd(can_config(dir, "can_refused", c.sink), dir + "/can_refused.out");
    EXPECT_NE(daemon.status, 0) << c.sink;
    EXPECT_NE(daemon.out.find(c.message), std::string::npos) << c.sink << "\n" << daemon.out;
  }
}
