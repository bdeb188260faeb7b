// Jiggle in physical units (metaballs-pbd-skinning, "Secondary deformation"):
// the swing decays within the time window W_t, and the same motion at 250 Hz
// and 1 kHz gives the same swing. The arm is carried sideways at a constant
// speed, then stopped dead; the swing is the error e = c - c_target of a
// jiggle ball, which about a still target is the damped oscillator that
// metaballs::jiggle_gains discretises exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "arm_scene.hpp"
#include "sim_core/metaballs/jiggle_gains.hpp"
#include "sim_core/metaballs/state.hpp"

namespace {

using sinew::test::ArmScene;
namespace mbb = sinew::metaballs_build;
namespace rigc = sinew::rigc;

constexpr double kPi = 3.14159265358979323846;
constexpr double kFrequency = 4.0;  // Hz
constexpr double kWindow = 0.4;     // W_t, s
constexpr double kSpeed = 0.5;      // m/s, sideways (+y)
constexpr double kMoveTime = 4 * kWindow;
constexpr double kWatchTime = 3 * kWindow;

// coupling: the springs between the region's balls and their neighbours
// (Hz, the builder's default; 0: each ball swings alone, the closed form).
mbb::Options jiggle_window_options(uint32_t rate_hz, double coupling) {
  mbb::Options o = sinew::test::arm_options();
  o.jiggle.push_back({"shoulder", 0.3, 0.7, 0.2});
  o.jiggle_frequency = kFrequency;
  o.jiggle_window = kWindow;
  o.jiggle_coupling = coupling;
  o.rate_hz = rate_hz;
  return o;
}

struct Swing {
  double dt = 0;
  double lsb = 0;             // metres per Len step
  double stiffness = 0;       // k
  double damping = 0;         // d
  std::vector<double> after;  // e_y (m) at each step after the stop
};

// Carries the arm at kSpeed for kMoveTime, stops it, records e_y of one
// jiggle ball for kWatchTime. The model is built for built_hz (0: rate_hz)
// and its gains converted to rate_hz at run time (set_tick_rate).
Swing run_swing(uint32_t rate_hz, bool jiggle_on, uint32_t built_hz = 0,
                double coupling = mbb::Options{}.jiggle_coupling) {
  Swing out;
  ArmScene s(rigc::SkinChoice::kDualQuaternion, jiggle_window_options(built_hz != 0 ? built_hz : rate_hz, coupling));
  EXPECT_TRUE(s.ok()) << s.error();
  if (!s.ok()) return out;
  EXPECT_TRUE(sinew::metaballs::set_tick_rate(&s.state(), rate_hz).ok());
  s.state().features.jiggle = jiggle_on;
  uint32_t ball = 0;
  while (ball < s.model().ball_count() && s.model().ball_jiggle[ball] == 0) ++ball;
  EXPECT_LT(ball, s.model().ball_count());
  out.dt = 1.0 / rate_hz;
  out.lsb = s.len(1);
  out.stiffness = std::ldexp(s.state().jiggle_stiffness[ball], -30);
  out.damping = std::ldexp(s.state().jiggle_damping[ball], -30);
  EXPECT_TRUE(s.pose(0, 0, 0));
  const std::vector<sinew::fx::Mat34> rest(s.engine().model.begin(), s.engine().model.end());
  std::vector<sinew::fx::Mat34> moved = rest;
  // The same speed at both rates: a whole number of Len steps per 1 ms.
  const auto per_1ms = static_cast<int64_t>(std::llround(kSpeed * 0.001 / out.lsb));
  const int64_t per_step = per_1ms * 1000 / static_cast<int64_t>(rate_hz);
  const auto move_steps = static_cast<int64_t>(std::llround(kMoveTime * rate_hz));
  const auto watch_steps = static_cast<int64_t>(std::llround(kWatchTime * rate_hz));
  for (int64_t n = 1; n <= move_steps + watch_steps; ++n) {
    const int64_t offset = per_step * std::min(n, move_steps);
    for (size_t j = 0; j < moved.size(); ++j) moved[j].t[1] = static_cast<int32_t>(rest[j].t[1] + offset);
    EXPECT_TRUE(sinew::metaballs::metaballs_step(&s.state(), moved, s.output()).ok());
    if (n >= move_steps)
      out.after.push_back(s.len(s.state().ball_center[ball].y) - s.len(s.state().ball_target[ball].y));
  }
  return out;
}

// The continuous swing the gains stand for: sigma = ln 20 / W_t, omega = 2 pi f.
double sigma() { return std::log(20.0) / kWindow; }
double omega() { return 2 * kPi * kFrequency; }

// The largest swing of the impulse response is at least its value a
// quarter period in: (u / omega) exp(-sigma pi / (2 omega)).
double least_first_swing() { return kSpeed / omega() * std::exp(-sigma() * kPi / (2 * omega())); }

// Each ball alone (no coupling springs): its swing is the closed form.
TEST(MetaballsJiggleWindow, SwingFallsBelowTheCriterionWithinTheWindow) {
  const Swing s = run_swing(1000, true, 0, 0.0);
  ASSERT_GT(s.after.size(), 10u);
  // Extrema of |e| after the stop; a damped sinusoid's extrema all lie on
  // A exp(-sigma t), so those W_t after the first are <= 5 % of it.
  std::vector<size_t> peaks;
  for (size_t i = 1; i + 1 < s.after.size(); ++i)
    if (std::fabs(s.after[i]) >= std::fabs(s.after[i - 1]) && std::fabs(s.after[i]) > std::fabs(s.after[i + 1]))
      peaks.push_back(i);
  ASSERT_GE(peaks.size(), 3u);
  const double first = std::fabs(s.after[peaks[0]]);
  // The sampled first peak is within cos(omega dt / 2) of the true one;
  // rounding adds a few LSB per step, damped (bounded by 64 LSB).
  const double bound = 0.05 * first / std::cos(omega() * s.dt / 2) + 64 * s.lsb;
  double worst_late = 0;
  size_t late = 0;
  for (size_t p : peaks)
    if ((static_cast<double>(p) - static_cast<double>(peaks[0])) * s.dt >= kWindow) {
      worst_late = std::max(worst_late, std::fabs(s.after[p]));
      ++late;
    }
  std::printf(
      "jiggle window: f %.1f Hz, W_t %.2f s, k %.6f d %.6f at 1 kHz; first swing %.3f mm, largest swing W_t "
      "later %.4f mm (%.2f %%, criterion 5 %%), %zu peaks, %zu after W_t\n",
      kFrequency, kWindow, s.stiffness, s.damping, first * 1e3, worst_late * 1e3, 100 * worst_late / first,
      peaks.size(), late);
  ASSERT_GT(late, 0u);
  EXPECT_LE(worst_late, bound);
  // The swing is there, as large as the continuous impulse response's.
  EXPECT_GE(first, 0.95 * least_first_swing()) << "no swing: jiggle off?";
  // Successive same-sign peaks one period apart: the frequency. The free
  // swing is the damped sinusoid sampled exactly, whose extrema lie half a
  // damped period 1 / (2 f) apart; a sampled extremum is one of the two
  // samples around the true one, within dt of it, so the measured period is
  // within 2 dt of 1 / f: |1 / period - f| <= f^2 2 dt / (1 - 2 f dt). The
  // Q2.30 gains put the frequency within a few 1e-6 of f (docs/metaballs.md):
  // 1e-5 f covers it.
  const double period = static_cast<double>(peaks[2] - peaks[0]) * s.dt;
  const double frequency_tol = kFrequency * kFrequency * 2 * s.dt / (1 - 2 * kFrequency * s.dt) + 1e-5 * kFrequency;
  std::printf("jiggle frequency: %.4f Hz (f %.1f Hz, bound +-%.4f Hz)\n", 1 / period, kFrequency, frequency_tol);
  EXPECT_NEAR(1 / period, kFrequency, frequency_tol);
}

TEST(MetaballsJiggleWindow, NoSwingWhenJiggleIsOff) {
  const Swing s = run_swing(1000, false);
  double worst = 0;
  for (double e : s.after) worst = std::max(worst, std::fabs(e));
  std::printf("jiggle off: largest |e| after the stop %.3g m\n", worst);
  EXPECT_LT(worst, 0.01 * least_first_swing());
}

TEST(MetaballsJiggleWindow, SameSwingAt250HzAnd1kHz) {
  const Swing slow = run_swing(250, true), fast = run_swing(1000, true);
  ASSERT_FALSE(slow.after.empty());
  ASSERT_FALSE(fast.after.empty());
  // Each rate samples the continuous swing: the free swing exactly, the
  // stop's impulse to within theta / sin(theta) - 1 <= theta^2 / 6 of its
  // amplitude u / omega (theta = 2 pi f dt). The start's impulse came at a
  // different tick at each rate but is left at 5 %^4 of u / omega after 4
  // W_t of motion. The Q2.30 gains shift omega by ~1e-6 relative: below
  // 1e-4 rad of phase over the watch. Rounding adds at most 64 LSB a rate.
  const double amplitude = kSpeed / omega();
  const double t_slow = omega() * slow.dt, t_fast = omega() * fast.dt;
  const double bound =
      amplitude * ((t_slow * t_slow + t_fast * t_fast) / 6 + 2 * std::pow(0.05, 4) + 1e-4) + 128 * fast.lsb;
  double worst = 0, peak = 0;
  for (size_t i = 0; i < slow.after.size() && 4 * i < fast.after.size(); ++i) {
    worst = std::max(worst, std::fabs(slow.after[i] - fast.after[4 * i]));
    peak = std::max(peak, std::fabs(fast.after[4 * i]));
  }
  std::printf(
      "jiggle 250 Hz vs 1 kHz: k %.6f / %.6f, d %.6f / %.6f; largest swing %.3f mm, largest difference %.4f mm "
      "(bound %.4f mm)\n",
      slow.stiffness, fast.stiffness, slow.damping, fast.damping, peak * 1e3, worst * 1e3, bound * 1e3);
  EXPECT_LE(worst, bound);
  EXPECT_GT(peak, 10 * bound);  // the bound is far below the swing itself
}

// The same motion with a model built for one rate and run at the other, the
// gains converted at run time, against the model built for the rate it
// runs at. The conversion recovers theta from Q2.30 gains: cos(theta) is
// known to within a few LSB (k and d each within 2 LSB of their exact
// values, exp_neg_unit and the rounding of the products), so theta to
// within 4 x 2^-30 / (theta sin theta) relative at the built rate, the
// same relative error at the run rate; over the watch that is a phase
// error of omega T_watch times it, on a swing of u / omega.
double conversion_bound(double built_dt) {
  const double theta = omega() * built_dt;
  return kSpeed / omega() * omega() * kWatchTime * 4 * std::ldexp(1.0, -30) / (theta * std::sin(theta));
}

TEST(MetaballsJiggleWindow, GainsConvertedAtRunTimeGiveTheSameSwing) {
  struct Case {
    uint32_t built_hz, run_hz;
  };
  const Swing at_250 = run_swing(250, true), at_1k = run_swing(1000, true);
  for (const Case c : {Case{1000, 250}, Case{250, 1000}}) {
    const Swing converted = run_swing(c.run_hz, true, c.built_hz);
    const Swing& native = c.run_hz == 250 ? at_250 : at_1k;
    const Swing& built = c.built_hz == 250 ? at_250 : at_1k;
    ASSERT_EQ(converted.after.size(), native.after.size());
    ASSERT_FALSE(converted.after.empty());
    double worst_native = 0, worst_built = 0, peak = 0;
    const size_t ratio_up = c.built_hz > c.run_hz ? c.built_hz / c.run_hz : 1;
    const size_t ratio_down = c.run_hz > c.built_hz ? c.run_hz / c.built_hz : 1;
    for (size_t i = 0; i < converted.after.size(); ++i) {
      worst_native = std::max(worst_native, std::fabs(converted.after[i] - native.after[i]));
      peak = std::max(peak, std::fabs(native.after[i]));
      // The built rate's samples at the same instants.
      if (i % ratio_down == 0 && (i / ratio_down) * ratio_up < built.after.size())
        worst_built = std::max(worst_built, std::fabs(converted.after[i] - built.after[(i / ratio_down) * ratio_up]));
    }
    const double fine_dt = std::min(converted.dt, built.dt), coarse_dt = std::max(converted.dt, built.dt);
    const double lsb = converted.lsb;
    // Against the model built for the run rate: the conversion's phase error
    // and 64 LSB of rounding a run.
    const double bound_native = conversion_bound(built.dt) + 128 * lsb;
    // Against the built rate itself: the two rates' sampling bound of
    // SameSwingAt250HzAnd1kHz plus the conversion's.
    const double amplitude = kSpeed / omega(), t1 = omega() * fine_dt, t2 = omega() * coarse_dt;
    const double bound_rates =
        amplitude * ((t1 * t1 + t2 * t2) / 6 + 2 * std::pow(0.05, 4) + 1e-4) + 128 * lsb + conversion_bound(built.dt);
    std::printf(
        "jiggle built for %u Hz, run at %u Hz: k %.9f d %.9f (built for %u Hz: %+.0f / %+.0f LSB); largest swing "
        "%.3f mm, difference from the model built for %u Hz %.5f mm (bound %.4f), from the %u Hz run %.4f mm "
        "(bound %.4f)\n",
        c.built_hz, c.run_hz, converted.stiffness, converted.damping, c.run_hz,
        std::ldexp(converted.stiffness - native.stiffness, 30), std::ldexp(converted.damping - native.damping, 30),
        peak * 1e3, c.run_hz, worst_native * 1e3, bound_native * 1e3, c.built_hz, worst_built * 1e3, bound_rates * 1e3);
    EXPECT_LE(worst_native, bound_native);
    EXPECT_LE(worst_built, bound_rates);
    EXPECT_GT(peak, 10 * bound_rates);
  }
}

TEST(MetaballsJiggleWindow, ConversionKeepsTheRateAndRefusesWhatCannotSwing) {
  sinew::metaballs::JiggleGains g, back;
  ASSERT_TRUE(sinew::metaballs::jiggle_gains(4 << 16, 26214, 1000, &g));
  ASSERT_TRUE(sinew::metaballs::jiggle_gains_for_rate(g, 1000, 1000, &back));
  EXPECT_EQ(back.stiffness, g.stiffness);  // the same rate: the gains unchanged
  EXPECT_EQ(back.damping, g.damping);
  EXPECT_FALSE(sinew::metaballs::jiggle_gains_for_rate(g, 1000, 12, &back));  // a quarter turn per tick
  EXPECT_FALSE(sinew::metaballs::jiggle_gains_for_rate(g, 1000, 0, &back));
  EXPECT_FALSE(sinew::metaballs::jiggle_gains_for_rate({0, g.damping}, 1000, 250, &back));
}

TEST(MetaballsJiggleWindow, GainsRejectATooSlowRate) {
  sinew::metaballs::JiggleGains g;
  EXPECT_TRUE(sinew::metaballs::jiggle_gains(4 << 16, 26214, 1000, &g));
  EXPECT_FALSE(sinew::metaballs::jiggle_gains(400 << 16, 26214, 1000, &g));  // a quarter turn per tick
  EXPECT_FALSE(sinew::metaballs::jiggle_gains(0, 26214, 1000, &g));
}

TEST(MetaballsJiggleWindow, ExpMatchesTheSeries) {
  for (double x : {0.0, 0.001, 0.01, 0.3, 0.5, 0.7, 1.5, 4.0, 10.0}) {
    const auto q = static_cast<int64_t>(std::llround(std::ldexp(x, 30)));
    EXPECT_NEAR(std::ldexp(sinew::metaballs::exp_neg_unit(q), -30), std::exp(-x), 1e-8) << x;
  }
}

}  // namespace
