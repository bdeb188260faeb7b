// The metaballs layer inside the daemon: the same inputs with and without
// `[layers] metaballs = true` give the same number of frames; with the layer
// the flexed elbow's skin differs from plain skinning by a bounded amount
// (volume preservation itself is tested in tests/sim_core/metaballs).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "hal/output/frame_log_reader.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "tests/integration/daemon_harness.hpp"

namespace {

std::vector<sinew::hal::output::DecodedPose> run(const std::string& name, const std::string& layers) {
  const std::string dir = testing::TempDir();
  const std::string config = dir + "/" + name + ".toml", log = dir + "/" + name + ".frames";
  std::remove(log.c_str());
  std::ofstream(config) << "[rig]\nbuiltin = \"arm\"\n[loop]\nrate_hz = 100\nduration_s = 1.0\nstats_interval_s = 0\n"
                        << "mode = \"offline\"\n[layers]\n"
                        << layers
                        << "\n[[source]]\ntype = \"simulated-rig\"\nperiod_ms = 10\n[[sink]]\ntype = \"log\"\npath = \""
                        << log << "\"\n";
  const sinew::test::DaemonRun daemon = sinew::test::run_sinewd(config, dir + "/" + name + ".out");
  EXPECT_EQ(daemon.status, 0) << daemon.command << "\n" << daemon.out;
  return sinew::test::read_frame_log(log).poses;
}

// The built-in arm is a tube about the x axis at rest (its joints lie on
// it): its thickest radius R is the largest distance of a rest vertex from
// that axis (metres). A layer that moved a vertex off plain skinning by the
// limb's diameter 2 R or more would have put it off its limb.
double arm_limb_radius() {
  double r = 0;
  for (const auto& v : sinew::rigc::builtin_arm().vertices) r = std::max(r, std::hypot(v.position[1], v.position[2]));
  return r;
}

}  // namespace

TEST(LayerEndToEnd, MetaballsLayerChangesTheSkinWithinBounds) {
  const auto plain = run("plain", ""), balls = run("metaballs", "metaballs = true");
  ASSERT_EQ(plain.size(), 100u);
  ASSERT_EQ(balls.size(), 100u);
  size_t differing_frames = 0;
  double largest_m = 0;
  for (size_t f = 0; f < plain.size(); ++f) {
    const auto& a = plain[f];
    const auto& b = balls[f];
    ASSERT_EQ(a.vertex_count, b.vertex_count);
    const double scale = std::ldexp(1.0, a.length_exponent - 20);  // Q12.20 rig units to metres
    bool differs = false;
    for (int c = 0; c < 3; ++c)
      for (size_t v = 0; v < a.vertex_count; ++v) {
        const double d = std::abs(static_cast<double>(a.position[c][v]) - b.position[c][v]) * scale;
        differs |= d > 0;
        largest_m = std::max(largest_m, d);
      }
    differing_frames += differs ? 1 : 0;
  }
  // Within the limb's diameter (the built-in arm's balls carry no bulge
  // gain, which would scale it by 1 + gain: tests/sim_core/pipeline/pipeline_test.cpp).
  const double limit = 2 * arm_limb_radius();
  std::printf(
      "metaballs vs plain skinning: %zu of %zu frames differ, largest vertex difference %.4f m (bound %.3f m)\n",
      differing_frames, plain.size(), largest_m, limit);
  EXPECT_GT(differing_frames, 50u);
  EXPECT_GT(largest_m, 1e-4);
  EXPECT_LT(largest_m, limit) << "the layer reshapes the skin, it does not tear it";
}

// [layers] only switches on what the rig carries: a layer asked of a blob
// compiled without layer tables (the core arm) is refused, naming the
// layers the rig does carry.
TEST(LayerEndToEnd, ALayerTheRigLacksIsRefused) {
  const std::string dir = testing::TempDir();
  const std::string blob = dir + "/core-arm.rig", config = dir + "/core-balls.toml";
  std::vector<uint8_t> bytes;
  sinew::rigc::CompileReport report;
  std::string error;
  ASSERT_TRUE(sinew::rigc::compile_rig(sinew::rigc::builtin_arm(), &bytes, &report, &error)) << error;
  std::ofstream(blob, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  std::ofstream(config) << "[rig]\nblob = \"" << blob << "\"\n[loop]\nduration_s = 1\nmode = \"offline\"\n"
                        << "[layers]\nmetaballs = true\n";
  const sinew::test::DaemonRun daemon = sinew::test::run_sinewd(config, dir + "/cb.out");
  EXPECT_EQ(WEXITSTATUS(daemon.status), 2);
  EXPECT_NE(daemon.out.find("[layers] metaballs = true, but the rig carries no such layer"), std::string::npos)
      << daemon.out;
}

// The largest skin move against plain skinning at the straightest and the
// deepest elbow of a run.
struct BulgeAtFlexion {
  double straight_deg, straight_mm, deep_deg, deep_mm;
  double lsb_mm;  // the frames' resolution: one Len LSB
};

BulgeAtFlexion bulge_at_flexion(const std::string& name, const std::string& layer) {
  const auto plain = run(name + "-plain", ""), layered = run(name, layer);
  EXPECT_EQ(plain.size(), 100u);
  EXPECT_EQ(layered.size(), plain.size());
  size_t straightest = 0, deepest = 0;
  std::vector<double> bulge(plain.size(), 0);
  for (size_t f = 0; f < plain.size() && f < layered.size(); ++f) {
    const double scale = std::ldexp(1.0, plain[f].length_exponent - 20);
    for (int c = 0; c < 3; ++c)
      for (size_t v = 0; v < plain[f].vertex_count; ++v)
        bulge[f] = std::max(bulge[f],
                            std::abs(static_cast<double>(plain[f].position[c][v]) - layered[f].position[c][v]) * scale);
    if (plain[f].input_value[sinew::test::kArmElbow] < plain[straightest].input_value[sinew::test::kArmElbow])
      straightest = f;
    if (plain[f].input_value[sinew::test::kArmElbow] > plain[deepest].input_value[sinew::test::kArmElbow]) deepest = f;
  }
  const auto deg = [&](size_t f) { return plain[f].input_value[sinew::test::kArmElbow] * (360.0 / 4294967296.0); };
  const double lsb_mm = plain.empty() ? 0 : std::ldexp(1.0, plain[0].length_exponent - 20) * 1e3;
  const BulgeAtFlexion b{deg(straightest), bulge[straightest] * 1e3, deg(deepest), bulge[deepest] * 1e3, lsb_mm};
  std::printf("%s vs plain skinning: elbow %.1f deg -> largest move %.2f mm; elbow %.1f deg -> %.2f mm\n", name.c_str(),
              b.straight_deg, b.straight_mm, b.deep_deg, b.deep_mm);
  return b;
}

// The bar-net's elbow bulge in the daemon's frames grows with flexion (its
// loads' activation rises with the elbow angle; eq. (4)'s size of it is
// checked in tests/sim_core/pipeline and tests/sim_core/barnet): by more than the frames'
// resolution, and within the limb's diameter.
TEST(LayerEndToEnd, BarnetBulgeGrowsWithElbowFlexion) {
  const BulgeAtFlexion b = bulge_at_flexion("barnet", "barnet = true");
  EXPECT_GT(b.deep_mm, b.straight_mm + b.lsb_mm);
  EXPECT_LT(b.deep_mm, 2 * arm_limb_radius() * 1e3);
}

// Muscles under an elastic skin: the skin moves off plain skinning more at
// deep flexion (the biceps bulge, the crease pushed out of the muscles) than
// near straight, by more than the frames' resolution. How far each skin
// vertex may lie from its anchor is bounded from the model in
// tests/sim_core/elastic_skin/skin_follows_bones_test.cpp; here the upper bound only rules
// out a blow-up in the daemon: no vertex leaves its limb (the diameter).
TEST(LayerEndToEnd, AnatomyBulgeGrowsWithElbowFlexion) {
  const BulgeAtFlexion b = bulge_at_flexion("anatomy", "anatomy = true");
  EXPECT_GT(b.deep_mm, b.straight_mm + b.lsb_mm);
  EXPECT_LT(b.deep_mm, 2 * arm_limb_radius() * 1e3);
}

// Every layer the built-in rigs carry, at once, in the daemon (offline,
// 100 Hz: the SPH gains are converted from the 1 kHz they were built for),
// printing each stage's share of the tick.
TEST(LayerEndToEnd, BuiltInRigsRunEveryLayerAtOnce) {
  for (const char* rig : {"arm", "hand"}) {
    const std::string dir = testing::TempDir();
    const std::string config = dir + "/all-" + rig + ".toml";
    std::ofstream(config) << "[rig]\nbuiltin = \"" << rig << "\"\n"
                          << "[loop]\nrate_hz = 100\nduration_s = 1.0\nstats_interval_s = 0\nmode = \"offline\"\n"
                          << "[layers]\nsph = true\nmetaballs = true\nbarnet = true\nanatomy = true\n"
                          << "[[source]]\ntype = \"trajectory\"\nname = \"sweep\"\nperiod_ms = 10\n";
    const sinew::test::DaemonRun daemon = sinew::test::run_sinewd(config, dir + "/all-" + rig + ".out");
    std::printf("%s", daemon.out.c_str());
    ASSERT_EQ(daemon.status, 0) << daemon.command << "\n" << daemon.out;
    EXPECT_NE(daemon.out.find("running: sph metaballs barnet anatomy"), std::string::npos) << daemon.out;
    EXPECT_NE(daemon.out.find("tick by stage"), std::string::npos) << daemon.out;
    EXPECT_EQ(daemon.out.find("layer errors"), std::string::npos) << daemon.out;
  }
}
