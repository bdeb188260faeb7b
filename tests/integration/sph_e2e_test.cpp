// The SPH elastic elbow inside the daemon, driven by the simulated rig: the
// rig's joints and the force sensor at the wrist ("elbow.force", an external
// input the layer declares) arrive on the simulated CAN bus. Against the same
// run without the layer: the force input is logged in every frame, the skin
// changes in every frame, and while the force makes the joint yield (Tresca)
// the elbow's input carries kJointYielded; the flag clears again once the
// force swings back (the yield is not latched).
// With the joints held, the bend stays within the force balance of the
// elastic pull; over Modbus, the force is the simulated sensor's signal.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "firmware/rig/loaded_rig.hpp"
#include "hal/common/pose_frame.hpp"
#include "hal/output/frame_log_reader.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "tests/integration/daemon_harness.hpp"

namespace {

using sinew::hal::output::DecodedPose;

// The simulated rig plays a robot arm here: its elbow input is a commanded
// target and the particles add the deflection under load, so the elbow is
// simulated although a source sends it (by default a sent DOF is measured).
constexpr const char* kSimulatedElbow = "sph = true\nsph_measured_from_sources = false";

// `extra`: more TOML after the simulated-rig source (its faults).
std::vector<DecodedPose> run_arm(const std::string& name, const std::string& layers, std::string* out,
                                 const std::string& extra = "") {
  const std::string dir = testing::TempDir();
  const std::string config = dir + "/" + name + ".toml", frames = dir + "/" + name + ".frames";
  std::remove(frames.c_str());
  std::ofstream(config) << "[rig]\nbuiltin = \"arm\"\n"
                        << "[loop]\nrate_hz = 100\nduration_s = 3.0\nstats_interval_s = 0\nmode = \"offline\"\n"
                        << "[layers]\n"
                        << layers << "\n[[source]]\ntype = \"simulated-rig\"\nperiod_ms = 10\n"
                        << extra << "[[sink]]\ntype = \"log\"\npath = \"" << frames << "\"\n";
  const sinew::test::DaemonRun daemon = sinew::test::run_sinewd(config, dir + "/" + name + ".out");
  EXPECT_EQ(daemon.status, 0) << daemon.command << "\n" << daemon.out;
  *out = daemon.out;
  return sinew::test::read_frame_log(frames).poses;
}

// The layer's elbow.force follows the arm's inputs.
constexpr int kElbow = sinew::test::kArmElbow, kForce = sinew::test::kArmInputs;

// The sensor's signal as the simulated rig sends it (hal/sim/rig_motion):
// input k swings over its declared range and 51/1024 past each limit, with
// a period of 2 + 0.37 k s; elbow.force is input 7, declared +-40 N.
constexpr double kForceAmplitude = 40.0 * (1 + 51.0 / 1024.0), kForcePeriod = 2.0 + 0.37 * 7;

TEST(SphEndToEnd, ForceInputBendsTheElbowUntilItYields) {
  std::string plain_out, sph_out;
  const std::vector<DecodedPose> plain = run_arm("sph-plain", "", &plain_out);
  const std::vector<DecodedPose> sph = run_arm("sph", kSimulatedElbow, &sph_out);
  ASSERT_EQ(plain.size(), 300u);
  ASSERT_EQ(sph.size(), plain.size());
  EXPECT_NE(sph_out.find("8 inputs (1 external)"), std::string::npos) << sph_out;

  double force_min = 0, force_max = 0, largest_mm = 0;
  size_t differing = 0, first_yield = sph.size(), cleared_after_yield = 0;
  for (size_t f = 0; f < sph.size(); ++f) {
    ASSERT_EQ(sph[f].input_count, kForce + 1u);
    ASSERT_EQ(plain[f].input_count, kForce + 1u) << "the rig declares elbow.force whether the layer runs or not";
    EXPECT_EQ(sph[f].input_value[kElbow], plain[f].input_value[kElbow]) << "the commanded elbow is logged unchanged";
    const double newtons = sph[f].input_value[kForce] / 65536.0;
    force_min = std::min(force_min, newtons);
    force_max = std::max(force_max, newtons);
    const bool yielded = (sph[f].input_status[kElbow] & sinew::hal::kJointYielded) != 0;
    if (yielded && first_yield == sph.size()) first_yield = f;
    cleared_after_yield += first_yield < f && !yielded ? 1 : 0;
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
      "skinning, largest vertex move %.2f mm; %zu frames after the first yield do not yield\n",
      force_min, force_max, first_yield,
      first_yield < sph.size() ? sph[first_yield].input_value[kForce] / 65536.0 : 0.0, differing, sph.size(),
      largest_mm, cleared_after_yield);
  // 3 s of A sin(2 pi t / T): its peak (T / 4 = 1.15 s) is sampled within a
  // tick (10 ms), and it is still falling at the end (the trough is at
  // 3 T / 4 = 3.44 s): the last frames, within two ticks of 3 s, are lowest.
  const double two_pi = 2 * 3.14159265358979323846;
  EXPECT_GE(force_max, kForceAmplitude * std::cos(two_pi * 0.010 / kForcePeriod));
  EXPECT_LE(force_max, kForceAmplitude + 32e-6);
  EXPECT_LE(force_min, kForceAmplitude * std::sin(two_pi * (3.0 - 0.020) / kForcePeriod));
  EXPECT_LT(first_yield, sph.size()) << "the force swing past the Tresca limit makes the elbow yield";
  EXPECT_GT(cleared_after_yield, 0u) << "the force swings back below the limit: the yield must not be latched";
  // The force is A sin(2 pi t / 4.59 s), non-zero from the first tick, and
  // the elbow swings: the layer changes the skin in every frame.
  EXPECT_EQ(differing, sph.size());
  EXPECT_GT(largest_mm, 0.0);
}

// The bend the particles give the elbow, against a force balance. The
// rig's joints are held at rest (their inputs dropped from the start), so
// the only motion is the bend, which turns the forearm and hand about the
// elbow's axis: recovered from the hand's far vertex, out of reach of the
// particles (eq. (2)), as the angle between its plain and its SPH position
// about that axis. Under a load torque tau on the distal particles the
// elastic pull k_e alone holds them, turned rigidly by theta, with the
// torque k_e sum m r_perp^2 sin(theta) (docs/sph.md); pressure only
// stiffens the joint and viscosity only damps it. A damped oscillator
// (k_e, c) under any load bounded by tau_max never deflects beyond
// (1 + q) / (1 - q) times its static deflection tau_max / (k_e sum m
// r_perp^2), q = exp(-pi zeta / sqrt(1 - zeta^2)), zeta = c / (2 sqrt(k_e))
// (the integral of |impulse response| over its integral). That linear bound
// b holds while the pull's sin(theta) >= theta (1 - b^2 / 6) keeps it at
// least (1 - b^2 / 6) as stiff: it is checked, divided by that, in the
// frames where b <= 0.5 rad (beyond, the tension alone could not hold the
// elbow at 42 N: the crease's pressure does). |tau| is at most the largest
// force seen in a tick the joint entered unyielded, times the lever: while
// it yields its load is held at its value when the yield began (§4.2). The elbow rests at its lower limit (0 deg), so
// an extending force is clamped: the bend seen is never negative; a flexing one bends it.
TEST(SphEndToEnd, BendStaysWithinTheForceBalance) {
  std::string plain_out, sph_out, hold;
  for (const char* joint :
       {"shoulder.0", "shoulder.1", "shoulder.2", "elbow.0", "forearm_twist.0", "wrist.0", "wrist.1"})
    hold += std::string("[[source.fault]]\nkind = \"drop\"\ninput = \"") + joint + "\"\nfrom_s = 0\nto_s = 100\n";
  const std::vector<DecodedPose> plain = run_arm("sph-held-plain", "", &plain_out, hold);
  const std::vector<DecodedPose> sph = run_arm("sph-held", kSimulatedElbow, &sph_out, hold);
  ASSERT_EQ(plain.size(), 300u);
  ASSERT_EQ(sph.size(), plain.size());

  // The compiled model the daemon runs (its embedded arm).
  sinew::firmware::LoadedRig rig;
  std::string error;
  ASSERT_TRUE(sinew::firmware::load_rig("arm", "", &rig, &error)) << error;
  ASSERT_EQ(rig.layers.sph.count, 1u);
  const sinew::sph::SphModel& m = rig.layers.sph.joint[0].model;
  const sinew::sph::SphParams& p = m.params;
  const double unit = std::ldexp(1.0, rig.rig.length_exponent), metres = unit / 1048576.0;
  const sinew::rigc::RigSpec spec = sinew::rigc::builtin_arm(sinew::rigc::SkinChoice::kDualQuaternion);
  const int elbow = sinew::rigc::joint_index(spec, "elbow");
  ASSERT_GE(elbow, 0);
  ASSERT_EQ(m.joint.distal_joint, static_cast<uint32_t>(elbow));
  // At rest every joint frame is a translation (the spec's rest rotations are identity).
  double centre[3] = {0, 0, 0};
  for (int j = elbow; j >= 0; j = spec.joints[static_cast<size_t>(j)].parent)
    for (int a = 0; a < 3; ++a) centre[a] += spec.joints[static_cast<size_t>(j)].translation[static_cast<size_t>(a)];
  const double n[3] = {m.joint.axis.x / 1073741824.0, m.joint.axis.y / 1073741824.0, m.joint.axis.z / 1073741824.0};
  const auto perp2 = [&](const double r[3]) {
    const double along = r[0] * n[0] + r[1] * n[1] + r[2] * n[2];
    return r[0] * r[0] + r[1] * r[1] + r[2] * r[2] - along * along;
  };
  double inertia = 0;  // sum over distal particles of r_perp^2, m^2
  for (uint32_t i = 0; i < m.particle_count(); ++i) {
    if (m.bone[i] != static_cast<uint8_t>(sinew::sph::Bone::kDistal)) continue;
    const double r[3] = {m.rest_model[0][i] * metres - centre[0], m.rest_model[1][i] * metres - centre[1],
                         m.rest_model[2][i] * metres - centre[2]};
    inertia += perp2(r);
  }
  const double lp[3] = {m.joint.load_point.x * metres, m.joint.load_point.y * metres, m.joint.load_point.z * metres};
  const double lever = std::sqrt(perp2(lp));
  // k_e m = elastic_gain / (load_gain unit): radians per newton of the static bend.
  const double bend_per_newton = lever * (static_cast<double>(p.load_gain) * unit) / (p.elastic_gain * inertia);
  const double substep_hz = static_cast<double>(rig.layers.rate_hz) * p.substeps;
  const double k_e = p.elastic_gain / 1073741824.0 * substep_hz * substep_hz;
  const double c = (1 - p.damping / 1073741824.0) * substep_hz;
  const double zeta = c / (2 * std::sqrt(k_e));
  const double q = std::exp(-3.14159265358979323846 * zeta / std::sqrt(1 - zeta * zeta));
  const double peak_factor = (1 + q) / (1 - q);

  // The hand's vertex farthest from the elbow's axis, outside eq. (2)'s reach.
  std::vector<bool> near(sph[0].vertex_count, false);
  for (uint32_t v : m.skin_vertex) near[v] = true;
  const double scale = std::ldexp(1.0, sph[0].length_exponent - 20);
  size_t far = 0;
  double far_r = 0;
  for (size_t v = 0; v < plain[0].vertex_count; ++v) {
    const double r[3] = {plain[0].position[0][v] * scale - centre[0], plain[0].position[1][v] * scale - centre[1],
                         plain[0].position[2][v] * scale - centre[2]};
    if (!near[v] && r[0] > 0 && perp2(r) > far_r * far_r) far = v, far_r = std::sqrt(perp2(r));
  }
  constexpr double kSmallAngle = 0.5;  // rad
  double force_bound = 0, worst_ratio = 0, largest_deg = 0;
  size_t first_yield = sph.size(), flexing = 0, bent = 0, bounded = 0;
  bool yielding = false;  // as the tick of frame f found the joint
  for (size_t f = 0; f < sph.size(); ++f) {
    const double newtons = sph[f].input_value[kForce] / 65536.0;
    if (!yielding) force_bound = std::max(force_bound, std::abs(newtons));
    yielding = (sph[f].input_status[kElbow] & sinew::hal::kJointYielded) != 0;
    if (yielding && first_yield == sph.size()) first_yield = f;
    double a[3], b[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = plain[f].position[k][far] * scale - centre[k];
      b[k] = sph[f].position[k][far] * scale - centre[k];
    }
    const double cross =
        n[0] * (a[1] * b[2] - a[2] * b[1]) + n[1] * (a[2] * b[0] - a[0] * b[2]) + n[2] * (a[0] * b[1] - a[1] * b[0]);
    const double an = a[0] * n[0] + a[1] * n[1] + a[2] * n[2], bn = b[0] * n[0] + b[1] * n[1] + b[2] * n[2];
    const double bend = std::atan2(cross, a[0] * b[0] + a[1] * b[1] + a[2] * b[2] - an * bn);
    const double linear = peak_factor * bend_per_newton * force_bound;
    largest_deg = std::max(largest_deg, bend * 57.29577951308232);
    if (linear > 0 && linear <= kSmallAngle) {
      const double limit = linear / (1 - linear * linear / 6);
      worst_ratio = std::max(worst_ratio, bend / limit);
      ++bounded;
      ASSERT_LE(bend, limit) << "frame " << f << ": beyond the force balance";
    }
    ASSERT_GE(bend, -1e-6) << "frame " << f << ": the elbow rests at its lower limit";
    flexing += newtons > 0 ? 1 : 0;
    bent += newtons > 0 && bend > 0 ? 1 : 0;
  }
  std::printf(
      "held joints: k_e %.0f /s^2, c %.1f /s, peak factor %.3f, static bend %.3f deg/N (lever %.3f m, sum r^2 "
      "%.4g m^2); yield at frame %zu of %zu; far vertex %.3f m from the axis: largest bend %.2f deg; %zu frames "
      "within the small-angle bound, at worst %.0f %% of it; %zu of %zu flexing frames bent\n",
      k_e, c, peak_factor, bend_per_newton * 57.29577951308232, lever, inertia, first_yield, sph.size(), far_r,
      largest_deg, bounded, worst_ratio * 100, bent, flexing);
  EXPECT_GT(bounded, 0u) << "the force rises from 0: its first frames are within the small-angle bound";
  EXPECT_GT(flexing, 0u);
  EXPECT_EQ(bent, flexing) << "a flexing force must bend the elbow";
}

// The force sensor read over Modbus: the simulated rig's CAN stream drops
// elbow.force for the whole run, so only the Modbus device (layout
// "simulated-rig", quantity force) can deliver it. Live, on loopback TCP.
// The rig declares elbow.force (and the frames log it) whether the SPH layer
// runs or not, so this live run leaves the layer off: the tests above show
// the layer's response to the force offline, where no tick is late.
//
// Load-proof (docs/testing.md): a live tick that runs late finds only samples
// stamped after its time and leaves the input stale, so how many frames are
// fresh depends on the machine. What is asserted holds at any speed: every
// fresh frame carries the sensor's signal, and the run saw at least one.
TEST(SphEndToEnd, ForceArrivesOverModbus) {
  const std::string dir = testing::TempDir();
  const std::string config = dir + "/sph-modbus.toml", frames = dir + "/sph-modbus.frames";
  std::remove(frames.c_str());
  const int port = 20000 + static_cast<int>((::getpid() + 7919) % 20000);
  // backoff_max_ms: a reply slowed past timeout_ms by a busy machine costs a
  // reconnect and at most 100 ms, not the default's 2 s of back-off.
  std::ofstream(config) << "[rig]\nbuiltin = \"arm\"\n"
                        << "[loop]\nrate_hz = 25\nduration_s = 2.0\nstats_interval_s = 0\nmode = \"live\"\n"
                        << "[[source]]\ntype = \"simulated-rig\"\nname = \"rig\"\nperiod_ms = 10\n"
                        << "modbus_port = " << port << "\n"
                        << "[[source.fault]]\nkind = \"drop\"\ninput = \"elbow.force\"\nfrom_s = 0\nto_s = 100\n"
                        << "[[source]]\ntype = \"modbus\"\nname = \"plc\"\nport = " << port
                        << "\nlayout = \"simulated-rig\"\ntimeout_ms = 50\nbackoff_max_ms = 100\nperiod_ms = 10\n"
                        << "[[sink]]\ntype = \"log\"\npath = \"" << frames << "\"\n";
  const sinew::test::DaemonRun daemon = sinew::test::run_sinewd(config, dir + "/sph-modbus.out");
  ASSERT_EQ(daemon.status, 0) << daemon.command << "\n" << daemon.out;
  const std::vector<DecodedPose> poses = sinew::test::read_frame_log(frames).poses;
  ASSERT_FALSE(poses.empty()) << daemon.out;  // late ticks are skipped, not every one
  // Every fresh frame must carry the simulated sensor's signal
  // A sin(2 pi (s0 + t) / T) at its tick's time t, with s0 the device's
  // start before the first tick (fitted, 1 ms steps over a second). The
  // device measures when a request arrives (hal/modbus/sim/modbus_feeder),
  // the poller stamps the sample when the reply is read, a reply later than
  // timeout_ms (50 ms) is a timeout and no sample, and a fresh input's last
  // sample is at most its timeout (1.5 periods: 15 ms) older than the
  // tick's time and never newer. So a fresh value was measured within
  // 15 + 50 ms before t: the tolerance is the signal's steepest change over
  // that span, plus half a fitting step. A wrong register scale, a sign or
  // another input's register misses it.
  double force_max = 0;
  size_t fed = 0;
  std::vector<std::pair<double, double>> fresh;  // (tick time s, newtons)
  for (const DecodedPose& p : poses) {
    ASSERT_EQ(p.input_count, kForce + 1u);
    const double newtons = p.input_value[kForce] / 65536.0;
    force_max = std::max(force_max, std::abs(newtons));
    if ((p.input_status[kForce] & sinew::hal::kJointStale) != 0) continue;
    ++fed;
    fresh.emplace_back(static_cast<double>(p.tick) / 25.0, newtons);
  }
  ASSERT_GE(fed, 1u) << "no frame carried a fresh force in " << poses.size() << " ticks\n" << daemon.out;
  const double two_pi = 2 * 3.14159265358979323846, slope = kForceAmplitude * two_pi / kForcePeriod;
  const double tolerance = slope * (0.015 + 0.050 + 0.0005);
  double best = 1e9, best_s0 = 0;
  for (int ms = 0; ms <= 1000; ++ms) {
    double worst = 0;
    for (const auto& [t, newtons] : fresh)
      worst =
          std::max(worst, std::abs(newtons - kForceAmplitude * std::sin(two_pi * (ms / 1000.0 + t) / kForcePeriod)));
    if (worst < best) best = worst, best_s0 = ms / 1000.0;
  }
  std::printf(
      "force over Modbus: %zu of %zu frames fresh, largest |force| %.2f N (amplitude %.2f N); against the signal "
      "started %.3f s before the first tick: worst %.3f N (tolerance %.3f N)\n",
      fed, poses.size(), force_max, kForceAmplitude, best_s0, best, tolerance);
  EXPECT_LE(best, tolerance) << "the force read over Modbus is not the sensor's signal\n" << daemon.out;
  // A register unit is 16 uN, Q16.16 15 uN: nothing beyond the amplitude.
  EXPECT_LE(force_max, kForceAmplitude + 32e-6);
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
