// The SPH elastic elbow inside the daemon, driven by the simulated rig: the
// rig's joints and the force sensor at the wrist ("elbow.force", an external
// input the layer declares) arrive on the simulated CAN bus. Against the same
// run without the layer: the force input is logged in every frame, the skin
// near the elbow moves by a bounded amount, and once the growing force makes
// the joint yield (Tresca) the elbow's input carries kJointYielded in every
// later frame.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "hal/common/pose_frame.hpp"
#include "hal/output/frame_log_reader.hpp"
#include "tests/integration/daemon_harness.hpp"

namespace {

using sinew::hal::output::DecodedPose;

std::vector<DecodedPose> run_arm(const std::string& name, const std::string& layers, std::string* out) {
  const std::string dir = testing::TempDir();
  const std::string config = dir + "/" + name + ".toml", frames = dir + "/" + name + ".frames";
  std::remove(frames.c_str());
  std::ofstream(config) << "[rig]\nbuiltin = \"arm\"\n"
                        << "[loop]\nrate_hz = 100\nduration_s = 3.0\nstats_interval_s = 0\nmode = \"offline\"\n"
                        << "[layers]\n"
                        << layers << "\n[[source]]\ntype = \"simulated-rig\"\nperiod_ms = 10\n"
                        << "[[sink]]\ntype = \"log\"\npath = \"" << frames << "\"\n";
  const sinew::test::DaemonRun daemon = sinew::test::run_sinewd(config, dir + "/" + name + ".out");
  EXPECT_EQ(daemon.status, 0) << daemon.command << "\n" << daemon.out;
  *out = daemon.out;
  return sinew::test::read_frame_log(frames).poses;
}

// The layer's elbow.force follows the arm's inputs.
constexpr int kElbow = sinew::test::kArmElbow, kForce = sinew::test::kArmInputs;

TEST(SphEndToEnd, ForceInputBendsTheElbowUntilItYields) {
  std::string plain_out, sph_out;
  const std::vector<DecodedPose> plain = run_arm("sph-plain", "", &plain_out);
  const std::vector<DecodedPose> sph = run_arm("sph", "sph = true", &sph_out);
  ASSERT_EQ(plain.size(), 300u);
  ASSERT_EQ(sph.size(), plain.size());
  EXPECT_NE(sph_out.find("8 inputs (1 external)"), std::string::npos) << sph_out;

  double force_min = 0, force_max = 0, largest_mm = 0;
  size_t differing = 0, first_yield = sph.size();
  for (size_t f = 0; f < sph.size(); ++f) {
    ASSERT_EQ(sph[f].input_count, kForce + 1u);
    ASSERT_EQ(plain[f].input_count, kForce + 1u) << "the rig declares elbow.force whether the layer runs or not";
    EXPECT_EQ(sph[f].input_value[kElbow], plain[f].input_value[kElbow]) << "the commanded elbow is logged unchanged";
    const double newtons = sph[f].input_value[kForce] / 65536.0;
    force_min = std::min(force_min, newtons);
    force_max = std::max(force_max, newtons);
    const bool yielded = (sph[f].input_status[kElbow] & sinew::hal::kJointYielded) != 0;
    if (yielded && first_yield == sph.size()) first_yield = f;
    if (first_yield < f) EXPECT_TRUE(yielded) << "frame " << f << ": the yield is latched";
    EXPECT_FALSE(plain[f].input_status[kElbow] & sinew::hal::kJointYielded);
    const double scale = std::ldexp(1.0, sph[f].length_exponent - 20);
    double frame_mm = 0;
    for (int c = 0; c < 3; ++c)
      for (size_t v = 0; v < sph[f].vertex_count; ++v)
        frame_mm = std::max(
            frame_mm, std::abs(static_cast<double>(sph[f].position[c][v]) - plain[f].position[c][v]) * scale * 1e3);
    differing += frame_mm > 0 ? 1 : 0;
    largest_mm = std::max(largest_mm, frame_mm);
  }
  std::printf(
      "force input %.1f .. %.1f N; joint yielded at frame %zu (%.1f N); %zu of %zu frames differ from plain "
      "skinning, largest vertex move %.2f mm\n",
      force_min, force_max, first_yield,
      first_yield < sph.size() ? sph[first_yield].input_value[kForce] / 65536.0 : 0.0, differing, sph.size(),
      largest_mm);
  EXPECT_LT(force_min, -30.0);
  EXPECT_GT(force_max, 40.0);
  EXPECT_LT(first_yield, sph.size()) << "the force swing past the Tresca limit makes the elbow yield";
  EXPECT_GT(differing, 250u);
  // The yielded joint bends about 25 deg under the load: the hand's end moves
  // about 150 mm. A bend past 45 deg (or a wrapped elbow angle, 0.5 m) fails.
  EXPECT_GT(largest_mm, 10.0);
  EXPECT_LT(largest_mm, 300.0) << "the particles flex the arm, they do not tear it";
}

// The force sensor read over Modbus: the simulated rig's CAN stream drops
// elbow.force for the whole run, so only the Modbus device (layout
// "simulated-rig", quantity force) can deliver it. Live, on loopback TCP.
TEST(SphEndToEnd, ForceArrivesOverModbus) {
  const std::string dir = testing::TempDir();
  const std::string config = dir + "/sph-modbus.toml", frames = dir + "/sph-modbus.frames";
  std::remove(frames.c_str());
  const int port = 20000 + static_cast<int>((::getpid() + 7919) % 20000);
  std::ofstream(config) << "[rig]\nbuiltin = \"arm\"\n"
                        << "[loop]\nrate_hz = 25\nduration_s = 2.0\nstats_interval_s = 0\nmode = \"live\"\n"
                        << "[layers]\nsph = true\n"
                        << "[[source]]\ntype = \"simulated-rig\"\nname = \"rig\"\nperiod_ms = 10\n"
                        << "modbus_port = " << port << "\n"
                        << "[[source.fault]]\nkind = \"drop\"\ninput = \"elbow.force\"\nfrom_s = 0\nto_s = 100\n"
                        << "[[source]]\ntype = \"modbus\"\nname = \"plc\"\nport = " << port
                        << "\nlayout = \"simulated-rig\"\ntimeout_ms = 50\nperiod_ms = 10\n"
                        << "[[sink]]\ntype = \"log\"\npath = \"" << frames << "\"\n";
  const sinew::test::DaemonRun daemon = sinew::test::run_sinewd(config, dir + "/sph-modbus.out");
  ASSERT_EQ(daemon.status, 0) << daemon.command << "\n" << daemon.out;
  const std::vector<DecodedPose> poses = sinew::test::read_frame_log(frames).poses;
  ASSERT_GE(poses.size(), 25u) << daemon.out;  // 50 ticks; late ones are skipped
  double force_max = 0;
  size_t fed = 0;
  for (const DecodedPose& p : poses) {
    ASSERT_EQ(p.input_count, kForce + 1u);
    force_max = std::max(force_max, std::abs(p.input_value[kForce] / 65536.0));
    fed += (p.input_status[kForce] & sinew::hal::kJointStale) == 0 ? 1 : 0;
  }
  std::printf("force over Modbus: %zu of %zu frames fresh, largest |force| %.2f N\n", fed, poses.size(), force_max);
  EXPECT_GT(force_max, 20.0) << daemon.out;
  EXPECT_LT(force_max, 45.0);
  EXPECT_GT(fed, poses.size() / 2) << daemon.out;
}

// The built-in arm's SPH joint is compiled for 1 kHz; other rates convert
// its gains at start-up (docs/pipeline.md), down to the rate whose 5 ms
// substeps number 16. Below that the daemon refuses, saying why.
TEST(SphEndToEnd, RefusesARateItsSubstepsCannotCover) {
  const std::string dir = testing::TempDir();
  const std::string config = dir + "/slow-sph.toml";
  std::ofstream(config) << "[rig]\nbuiltin = \"arm\"\n[loop]\nrate_hz = 5\nduration_s = 1\nmode = \"offline\"\n"
                        << "[layers]\nsph = true\n";
  const sinew::test::DaemonRun daemon = sinew::test::run_sinewd(config, dir + "/slow-sph.out");
  EXPECT_EQ(WEXITSTATUS(daemon.status), 2);
  EXPECT_NE(daemon.out.find("more than 16 substeps"), std::string::npos) << daemon.out;
}

}  // namespace
