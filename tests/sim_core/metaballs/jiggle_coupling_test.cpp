// Jiggle balls coupled by the paper's springs (metaballs-pbd-skinning,
// "Secondary deformation": "the positions of the balls in S_in are modified
// through the elasticity of springs"; eq. (3) C = |c_i - c_j| - d), in
// physical units (jiggle_gains.hpp). A bone along x carries a row of balls
// `spacing` apart; the middle ones jiggle, the end ones are kinematic.
//
// - Physics: one jiggle ball between two kinematic ones swings along the row
//   as e'' + 2 sigma e' + (omega0^2 + 2 omega_c^2) e = 0 (two springs of
//   omega_c^2 per unit mass), across it as e'' + 2 sigma e' + omega0^2 e = 0
//   (a spring without tension has no transverse stiffness to first order).
// - Oracle: each step of the fixed-point layer against the same step in
//   double, from the layer's own state (the recurrence of pbd.cpp written
//   from its equations).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "sim_core/metaballs/jiggle_gains.hpp"
#include "sim_core/metaballs/state.hpp"
#include "sim_core/metaballs/step.hpp"

// Named: the unity build shares one translation unit with the window test.
namespace jiggle_coupling_test {
namespace {

namespace mb = sinew::metaballs;
namespace fx = sinew::fx;

constexpr double kPi = 3.14159265358979323846;
constexpr double kFrequency = 4.0;  // f, Hz
constexpr double kWindow = 0.4;     // W_t, s
constexpr double kCoupling = 4.0;   // f_c, Hz
constexpr double kSpacing = 0.05;   // rig units (1 unit = 1 m here)
constexpr double kSpeed = 0.5;      // units / s
constexpr double kLsb = 1.0 / (1 << 20);

int32_t len(double units) { return static_cast<int32_t>(std::llround(units / kLsb)); }

// A row of `balls` balls on one bone; `jiggle[i]` marks the jiggle ones.
// Neighbours are paired when one of them jiggles.
class Row {
 public:
  Row(const std::vector<bool>& jiggle, uint32_t rate_hz, double coupling_hz) {
    const size_t n = jiggle.size();
    mb::JiggleGains g;
    ok_ =
        mb::jiggle_gains(static_cast<int32_t>(kFrequency * 65536), static_cast<int32_t>(kWindow * 65536), rate_hz, &g);
    const fx::Unit x = mb::coupling_stiffness(static_cast<int32_t>(coupling_hz * 65536), rate_hz);
    inverse_bind_ = {fx::Mat34{}};
    for (int i = 0; i < 3; ++i) inverse_bind_[0].m[i][i] = 1 << 24;
    for (size_t i = 0; i < n; ++i) {
      rest_.push_back({len(kSpacing * static_cast<double>(i)), 0, 0});
      radius_.push_back(len(kSpacing));
      bone_.push_back(0);
      joint_.insert(joint_.end(), {0, 0});
      weight_.insert(weight_.end(), {fx::kUnitOne, 0});
      ball_jiggle_.push_back(jiggle[i] ? g.stiffness : 0);
      if (i > 0 && (jiggle[i] || jiggle[i - 1]) && x > 0)
        pairs_.push_back({static_cast<uint16_t>(i - 1), static_cast<uint16_t>(i), len(kSpacing), 1 << 29, 1 << 29, x});
    }
    vertex_ball_ = {0, mb::kNoBall, mb::kNoBall, mb::kNoBall};
    vertex_weight_ = {fx::kUnitOne, 0, 0, 0};
    vertex_disp_.assign(4, fx::Vec3{0, 0, 0});
    m_.joint_count = 1;
    m_.vertex_count = 1;
    m_.inverse_bind = inverse_bind_;
    m_.ball_rest = rest_;
    m_.ball_radius = radius_;
    m_.ball_bone = bone_;
    m_.ball_joint = joint_;
    m_.ball_weight = weight_;
    m_.ball_jiggle = ball_jiggle_;
    m_.pairs = pairs_;
    m_.pbd_iterations = 1;
    m_.jiggle_damping = g.damping;
    m_.jiggle_rate_hz = rate_hz;
    m_.vertex_ball = vertex_ball_;
    m_.vertex_weight = vertex_weight_;
    m_.vertex_disp = vertex_disp_;
    m_.jv_neighbour_begin = jv_begin_;
    memory_.assign(mb::metaballs_state_bytes(m_) / 8 + 1, 0);
    const mb::LayerStatus st = mb::metaballs_init(m_, memory_.data(), memory_.size() * 8, &s_);
    EXPECT_TRUE(st.ok()) << st.message;
    ok_ = ok_ && st.ok();
    for (auto& a : out_) a.assign(1, 0);
  }
  bool ok() const { return ok_; }
  mb::MetaballState& state() { return s_; }
  const mb::MetaballModel& model() const { return m_; }
  // One step with the bone translated by (tx, ty) Len.
  bool step(int64_t tx, int64_t ty) {
    std::vector<fx::Mat34> bone = inverse_bind_;
    bone[0].t[0] = static_cast<int32_t>(tx);
    bone[0].t[1] = static_cast<int32_t>(ty);
    sinew::skin::SkinnedVertices out;
    for (int a = 0; a < 3; ++a) out.position[a] = out_[a];
    return mb::metaballs_step(&s_, bone, out).ok();
  }

 private:
  bool ok_ = false;
  std::vector<fx::Mat34> inverse_bind_;
  std::vector<fx::Vec3> rest_;
  std::vector<fx::Len> radius_;
  std::vector<uint16_t> bone_, joint_;
  std::vector<fx::Unit> weight_, ball_jiggle_;
  std::vector<mb::BallPair> pairs_;
  std::vector<uint16_t> vertex_ball_;
  std::vector<fx::Unit> vertex_weight_;
  std::vector<fx::Vec3> vertex_disp_;
  std::vector<uint32_t> jv_begin_{0};
  mb::MetaballModel m_;
  std::vector<uint64_t> memory_;
  mb::MetaballState s_;
  std::vector<int32_t> out_[3];
};

struct Swing {
  double dt = 0;
  std::vector<double> after;  // the middle ball's swing along the motion, units
};

// Moves the row at `speed` along x (along = true) or y for 4 W_t, stops it
// dead and records the swing of ball 1 for 3 W_t.
Swing run(bool along, uint32_t rate_hz, double coupling_hz, double speed = kSpeed) {
  Swing out;
  Row row({false, true, false}, rate_hz, coupling_hz);
  if (!row.ok()) return out;
  out.dt = 1.0 / rate_hz;
  const int64_t per_step = len(speed / rate_hz);
  const auto move = static_cast<int64_t>(std::llround(4 * kWindow * rate_hz));
  const auto watch = static_cast<int64_t>(std::llround(3 * kWindow * rate_hz));
  for (int64_t n = 0; n <= move + watch; ++n) {
    const int64_t offset = per_step * std::min(n, move);
    EXPECT_TRUE(row.step(along ? offset : 0, along ? 0 : offset));
    const fx::Vec3 c = row.state().ball_center[1], t = row.state().ball_target[1];
    if (n >= move) out.after.push_back(((along ? c.x - t.x : c.y - t.y)) * kLsb);
  }
  return out;
}

// The measured frequency: successive same-sign extrema one damped period
// apart, each within dt of the true one.
double measured_frequency(const Swing& s, std::vector<size_t>* peaks_out = nullptr) {
  std::vector<size_t> peaks;
  for (size_t i = 1; i + 1 < s.after.size(); ++i)
    if (std::fabs(s.after[i]) >= std::fabs(s.after[i - 1]) && std::fabs(s.after[i]) > std::fabs(s.after[i + 1]))
      peaks.push_back(i);
  if (peaks_out != nullptr) *peaks_out = peaks;
  if (peaks.size() < 3) return 0;
  return 1 / (static_cast<double>(peaks[2] - peaks[0]) * s.dt);
}

// The damped frequency (Hz) of the discrete recurrence for a mode whose
// springs add lambda = (omega_c h)^2 times `springs` (pbd.cpp):
// z^2 - ((1 - k)(1 + d) - r lambda) z + (1 - k) d = 0, |z| = r.
double discrete_frequency(uint32_t rate_hz, double springs) {
  mb::JiggleGains g;
  mb::jiggle_gains(static_cast<int32_t>(kFrequency * 65536), static_cast<int32_t>(kWindow * 65536), rate_hz, &g);
  const double k = std::ldexp(g.stiffness, -30), d = std::ldexp(g.damping, -30);
  const double x = std::ldexp(mb::coupling_stiffness(static_cast<int32_t>(kCoupling * 65536), rate_hz), -30);
  const double r = std::sqrt((1 - k) * d);
  const double c = ((1 - k) * (1 + d) - r * springs * x) / (2 * r);
  return std::acos(c) * rate_hz / (2 * kPi);
}

// The continuous damped frequency (Hz): omega_d^2 = omega0^2 + springs
// omega_c^2 - sigma^2 = omega^2 + springs omega_c^2.
double continuous_frequency(double springs) {
  const double w = 2 * kPi * kFrequency, wc = 2 * kPi * kCoupling;
  return std::sqrt(w * w + springs * wc * wc) / (2 * kPi);
}

TEST(MetaballsJiggleCoupling, AlongTheRowTheSwingTakesBothSprings) {
  for (const uint32_t rate : {250u, 1000u}) {
    const Swing s = run(true, rate, kCoupling);
    std::vector<size_t> peaks;
    const double measured = measured_frequency(s, &peaks);
    ASSERT_GE(peaks.size(), 3u);
    const double want = continuous_frequency(2), discrete = discrete_frequency(rate, 2);
    // Sampling: the period is within 2 dt (|1/T - f| <= f^2 2 dt / (1 - 2 f
    // dt)); the scheme's own frequency differs from the continuous one by
    // |discrete - want| (second order in h), and the Q2.30 gains by 1e-5 f.
    const double tol = want * want * 2 * s.dt / (1 - 2 * want * s.dt) + std::fabs(discrete - want) + 1e-5 * want;
    // The springs add no damping: the envelope still falls to 5 % within
    // W_t (|z| = r), here checked on the extrema W_t after the first.
    double first = std::fabs(s.after[peaks[0]]), late = 0;
    for (size_t p : peaks)
      if (static_cast<double>(p - peaks[0]) * s.dt >= kWindow) late = std::max(late, std::fabs(s.after[p]));
    std::printf(
        "coupled swing along the row at %u Hz: %.4f Hz (continuous %.4f, scheme %.4f, bound +-%.4f; alone %.1f); "
        "first %.3f mm, W_t later %.2f %%\n",
        rate, measured, want, discrete, tol, kFrequency, first * 1e3, 100 * late / first);
    EXPECT_NEAR(measured, want, tol);
    // The sampled extremum is within cos(omega dt / 2) of the true one, plus
    // 64 LSB of rounding.
    EXPECT_LE(late, 0.05 * first / std::cos(2 * kPi * want * s.dt / 2) + 64 * kLsb);
  }
}

TEST(MetaballsJiggleCoupling, AcrossTheRowTheSwingIsTheBallsOwn) {
  // A fifth of the speed: a swing of about 2 mm against the 50 mm spacing.
  const Swing s = run(false, 1000, kCoupling, kSpeed / 5);
  const double measured = measured_frequency(s);
  double amplitude = 0;
  for (double e : s.after) amplitude = std::max(amplitude, std::fabs(e));
  // Across the row a spring pulls only at second order: stretched by
  // e^2 / 2d, it pulls back x e^2 / 2d along a direction e / d across, so
  // each of the two adds at most omega_c^2 e^2 / (2 d^2) to omega0^2:
  // f' <= f sqrt(1 + omega_c^2 a^2 / (omega0^2 d^2)) at the largest swing a.
  // Plus the sampling of the period (2 dt) and the gains (1e-5 f).
  const double w0sq = std::pow(2 * kPi * kFrequency, 2) + std::pow(std::log(20.0) / kWindow, 2);
  const double nonlinear =
      kFrequency * (std::sqrt(1 + std::pow(2 * kPi * kCoupling * amplitude / kSpacing, 2) / w0sq) - 1);
  const double tol = kFrequency * kFrequency * 2 * s.dt / (1 - 2 * kFrequency * s.dt) + 1e-5 * kFrequency + nonlinear;
  std::printf("coupled swing across the row: %.4f Hz (f %.1f, bound +-%.4f; largest swing %.3f mm)\n", measured,
              kFrequency, tol, amplitude * 1e3);
  EXPECT_NEAR(measured, kFrequency, tol);
}

// The step in double, from the layer's own state before it: the kinematic
// centres, each pair's pull x C (c_a - c_b) / |c_a - c_b| from the centres
// at the start of the tick, and the swing recurrence with the pull entering
// as the bone's acceleration does.
std::vector<std::array<double, 3>> oracle_step(const mb::MetaballModel& m, const mb::MetaballState& s,
                                               const std::vector<std::array<double, 3>>& target) {
  const size_t n = m.ball_count();
  std::vector<std::array<double, 3>> c(n), pull(n, {0, 0, 0});
  const auto d3 = [](fx::Vec3 v) { return std::array<double, 3>{double(v.x), double(v.y), double(v.z)}; };
  for (size_t p = 0; p < m.pairs.size(); ++p) {
    const auto& q = m.pairs[p];
    const auto a = d3(s.ball_center[q.a]), b = d3(s.ball_center[q.b]);
    const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    const double l = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double f = std::ldexp(s.pair_coupling[p], -30) * (l - q.rest) / l;
    const double fv[3] = {f * dx, f * dy, f * dz};
    for (int i = 0; i < 3; ++i) {
      if (m.ball_jiggle[q.a] != 0) pull[q.a][static_cast<size_t>(i)] -= fv[i];
      if (m.ball_jiggle[q.b] != 0) pull[q.b][static_cast<size_t>(i)] += fv[i];
    }
  }
  for (size_t b = 0; b < n; ++b) {
    if (m.ball_jiggle[b] == 0) {
      c[b] = target[b];
      continue;
    }
    const double kept = 1 - std::ldexp(s.jiggle_stiffness[b], -30), d = std::ldexp(s.jiggle_damping[b], -30);
    const double drive = std::sqrt(kept * d);
    const auto centre = d3(s.ball_center[b]), last = d3(s.ball_last_target[b]), last_step = d3(s.ball_last_step[b]);
    for (size_t i = 0; i < 3; ++i) {
      // The swing as the layer carries it: whole steps in the centre, the
      // fraction below (swing_fraction, swing_previous: 2^-24 LSB).
      const double e = centre[i] - last[i] + std::ldexp(double(s.swing_fraction[3 * b + i]), -24);
      const double prev = std::ldexp(double(s.swing_previous[3 * b + i]), -24);
      const double step = target[b][i] - last[i];
      const double accel = step - last_step[i];
      c[b][i] = target[b][i] + kept * (e + d * (e - prev)) - drive * (accel - pull[b][i]);
    }
  }
  return c;
}

TEST(MetaballsJiggleCoupling, EachStepMatchesTheDoubleOracle) {
  // Two jiggle balls between kinematic ones (a pair of two jiggle balls), a
  // path along and across the row with a stop, at both rates.
  for (const uint32_t rate : {250u, 1000u}) {
    Row row({false, true, true, false}, rate, kCoupling);
    ASSERT_TRUE(row.ok());
    const mb::MetaballModel& m = row.model();
    const int64_t per_step = len(kSpeed / rate);
    const auto steps = static_cast<int64_t>(std::llround(2 * kWindow * rate));
    double worst = 0;
    for (int64_t n = 0; n < 2 * steps; ++n) {
      const int64_t tx = per_step * std::min(n, steps), ty = (per_step / 2) * std::min(n, steps / 2);
      const bool primed = row.state().primed;
      std::vector<std::array<double, 3>> target(m.ball_count());
      for (size_t b = 0; b < target.size(); ++b)
        target[b] = {double(m.ball_rest[b].x + tx), double(m.ball_rest[b].y + ty), double(m.ball_rest[b].z)};
      const auto want = oracle_step(m, row.state(), target);
      ASSERT_TRUE(row.step(tx, ty));
      if (!primed) continue;  // the first step places every ball on its centre
      for (size_t b = 0; b < want.size(); ++b) {
        const fx::Vec3 got = row.state().ball_center[b];
        worst = std::max(
            {worst, std::fabs(got.x - want[b][0]), std::fabs(got.y - want[b][1]), std::fabs(got.z - want[b][2])});
      }
    }
    // The swing and the pull are carried 24 bits below the Len step and
    // rounded once into the centre (0.5 LSB); before that, the pull's length
    // is an integer root (within 1 LSB, times x <= 1, times drive) and its
    // direction within 2^-29 of unit, two pairs per ball: 2 LSB; the drive's
    // Q2.30 root adds below 1e-6 LSB here. 2.5 LSB; bound 4.
    std::printf("coupled jiggle vs double oracle at %u Hz: largest one-step gap %.2f LSB (bound 4)\n", rate, worst);
    EXPECT_LE(worst, 4.0);
    EXPECT_GT(row.state().stats.steps, 0u);
  }
}

TEST(MetaballsJiggleCoupling, TooStiffForTheRateIsRefused) {
  // 60 Hz springs built for 1 kHz: x = (2 pi 60 / 1000)^2 = 0.142.
  Row row({false, true, false}, 1000, 60.0);
  ASSERT_TRUE(row.ok());
  const fx::Unit before = row.state().pair_coupling[0];
  // At 100 Hz x' = 14.2, beyond what a spring step can carry; at 300 Hz
  // x' = 1.58 per pair, and the ball's two springs exceed the swing's
  // stability bound (Gershgorin 4 x' = 6.3 against Jury's ~3.9). Both are
  // refused naming the springs, and the state keeps its gains.
  for (const uint32_t rate : {100u, 300u}) {
    const mb::LayerStatus st = mb::set_tick_rate(&row.state(), rate);
    EXPECT_FALSE(st.ok()) << rate;
    EXPECT_NE(std::string(st.message).find("coupling"), std::string::npos) << st.message;
    EXPECT_EQ(row.state().pair_coupling[0], before);
  }
  // At 500 Hz it converts: x (1000 / 500)^2, within the two roundings.
  ASSERT_TRUE(mb::set_tick_rate(&row.state(), 500).ok());
  EXPECT_NEAR(row.state().pair_coupling[0], 4.0 * before, 4.0);
}

}  // namespace
}  // namespace jiggle_coupling_test
