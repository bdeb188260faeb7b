// End to end through the daemon binary with the simulated rig's quadrature
// encoders on a simulated GPIO chip: the forearm twist (no index line, zero
// at its power-up pose) is decoded into the frames from the first tick, the
// elbow (index line at 75 deg) only once its zero mark has passed, and a
// window of encoder glitches is counted, degrades the source and leaves the
// angles right.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "hal/common/pose_frame.hpp"
#include "hal/output/frame_log_reader.hpp"
#include "tests/integration/daemon_harness.hpp"

namespace {

using sinew::hal::output::DecodedPose;

using sinew::test::kArmElbow;
using sinew::test::kArmTwist;

// Binary angle to degrees in [-180, 180).
double degrees(int32_t angle) { return angle / 4294967296.0 * 360.0; }

TEST(GpioEndToEnd, SimulatedEncodersDriveTheArm) {
  const std::string dir = testing::TempDir();
  const std::string config = dir + "/gpio_e2e.toml", out = dir + "/gpio_e2e.out", frames = dir + "/gpio_e2e.frames";
  std::remove(frames.c_str());
  std::ofstream(config)
      << "[rig]\nbuiltin = \"arm\"\n"
         "[loop]\nrate_hz = 100\nduration_s = 3.0\nstats_interval_s = 0\nmode = \"offline\"\n"
         "[inputs]\ndefault_period_ms = 10.0\n"
         "[[source]]\ntype = \"gpio\"\nname = \"encoders\"\nchip = \"simulated-rig\"\nupdate_ms = 5.0\n"
         "[[source.encoder]]\ninput = \"forearm_twist.0\"\nline_a = 0\nline_b = 1\n"
         "counts_per_turn = 2048\n"
         "[[source.encoder]]\ninput = \"elbow.0\"\nline_a = 2\nline_b = 3\nline_index = 4\n"
         "counts_per_turn = 3600\noffset_deg = 75.0\n"
         "[[source.fault]]\nkind = \"encoder-glitch\"\ninput = \"forearm_twist.0\"\n"
         "from_s = 2.0\nto_s = 2.1\n"
         "[[sink]]\ntype = \"log\"\npath = \""
      << frames << "\"\n";
  const sinew::test::DaemonRun daemon = sinew::test::run_sinewd(config, out);
  const std::string& report = daemon.out;
  ASSERT_EQ(daemon.status, 0) << daemon.command << "\n" << report;
  std::printf("%s", report.c_str());

  const std::vector<DecodedPose> poses = sinew::test::read_frame_log(frames).poses;
  ASSERT_EQ(poses.size(), 300u) << "a frame for every tick";

  // The twist swings +-105 deg (its range and 5 % past it) in 3.48 s.
  double twist_min = 0, twist_max = 0;
  for (const DecodedPose& p : poses) {
    twist_min = std::min(twist_min, degrees(p.input_value[kArmTwist]));
    twist_max = std::max(twist_max, degrees(p.input_value[kArmTwist]));
    EXPECT_FALSE(p.input_status[kArmTwist] & sinew::hal::kJointStale);
  }
  std::printf("twist decoded over %.1f .. %.1f deg\n", twist_min, twist_max);
  EXPECT_LT(twist_min, -60.0);
  EXPECT_GT(twist_max, 95.0);

  // Not homed: the elbow has no sample (stale) until the swing brings it back
  // to 75 deg after half of its 3.11 s period; homed, it follows the swing
  // down past its 0 deg limit.
  EXPECT_TRUE(poses[100].input_status[kArmElbow] & sinew::hal::kJointStale);
  EXPECT_FALSE(poses[170].input_status[kArmElbow] & sinew::hal::kJointStale);
  double elbow_min = 180;
  for (size_t i = 170; i < poses.size(); ++i) elbow_min = std::min(elbow_min, degrees(poses[i].input_value[kArmElbow]));
  std::printf("elbow homed, then down to %.1f deg\n", elbow_min);
  EXPECT_LT(elbow_min, 5.0);

  // The glitch window: one glitch per 5 ms update for 0.1 s, each two illegal
  // transitions; the kernel-sized event FIFO (16 per line) never overflowed.
  EXPECT_NE(report.find("illegal 40, missed 0, resyncs 0"), std::string::npos) << report;
  EXPECT_NE(report.find("glitches injected 20"), std::string::npos) << report;
}

}  // namespace
