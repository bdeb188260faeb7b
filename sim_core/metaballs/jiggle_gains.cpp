#include "jiggle_gains.hpp"

#include "sim_core/fixed/scalar.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "sim_core/fixed/trig.hpp"

namespace sinew::metaballs {
namespace {

// ln(20) in Q2.30: round(2.995732273553991 x 2^30).
constexpr int64_t kLnInverseCriterion = 3216574480;

}  // namespace

fx::Unit exp_neg_unit(int64_t x_q30) {
  if (x_q30 <= 0) return fx::kUnitOne;
  if (x_q30 >= int64_t{32} << fx::kUnitFracBits) return 0;  // below 2^-46
  // Range reduction: exp(-x) = exp(-x / 2^h)^(2^h) with x / 2^h <= 1/2, then
  // the Taylor series to 12 terms (the 13th is below 2^-40); each term and
  // each squaring rounds once (products of two Q2.30 values < 2^62).
  int halvings = 0;
  while ((x_q30 >> halvings) > (fx::kUnitOne >> 1)) ++halvings;
  const int64_t y = x_q30 >> halvings;  // exact when halvings == 0
  int64_t term = fx::kUnitOne, sum = term;
  for (int n = 1; n <= 12 && term != 0; ++n) {
    term = -fx::round_shift(term * y, fx::kUnitFracBits) / n;
    sum += term;
  }
  for (int h = 0; h < halvings; ++h) sum = fx::round_shift(sum * sum, fx::kUnitFracBits);
  return static_cast<fx::Unit>(sum);
}

namespace {

// The gains whose integrator roots are r exp(+-i theta), r = exp(-sigma dt):
// 1 - k = 2 r cos(theta) - r^2, d = r^2 / (1 - k). theta: turns as a binary
// angle (2^32 a turn); sigma_dt: Q2.30.
bool gains_from_roots(uint64_t theta, int64_t sigma_dt, JiggleGains* out) {
  if (theta >= fx::kQuarterTurn || sigma_dt <= 0) return false;
  const int64_t r = exp_neg_unit(sigma_dt);
  const int64_t c = fx::cos_unit(static_cast<fx::Angle>(theta));
  const int64_t r2 = fx::round_shift(r * r, fx::kUnitFracBits);
  const int64_t kept = fx::round_shift(2 * r * c, fx::kUnitFracBits) - r2;  // 1 - k
  if (kept <= 0 || kept <= r2 || kept > fx::kUnitOne) return false;
  const int64_t damping = (r2 << fx::kUnitFracBits) / kept;  // d = r^2 / (1 - k) < 1
  if (damping >= fx::kUnitOne) return false;
  out->stiffness = static_cast<fx::Unit>(fx::kUnitOne - kept);
  out->damping = static_cast<fx::Unit>(damping);
  return out->stiffness > 0;
}

// -ln(x) for x in (0, 1], Q2.30 in and out: 2 atanh(y), y = (1 - x) / (1 + x)
// in [0, 1), series 2 (y + y^3 / 3 + y^5 / 5 + ...) until a term rounds to 0.
int64_t neg_ln_unit(int64_t x) {
  const int64_t y = ((fx::kUnitOne - x) << fx::kUnitFracBits) / (fx::kUnitOne + x);  // < 2^31: fits before the shift
  const int64_t y2 = fx::round_shift(y * y, fx::kUnitFracBits);
  int64_t power = y, sum = 0;
  for (int64_t n = 1; n < 2000 && power != 0; n += 2) {
    sum += power / n;
    power = fx::round_shift(power * y2, fx::kUnitFracBits);
  }
  return 2 * sum;
}

}  // namespace

bool jiggle_gains(int32_t frequency_q16, int32_t window_q16, uint32_t tick_hz, JiggleGains* out) {
  if (frequency_q16 <= 0 || window_q16 <= 0 || tick_hz == 0) return false;
  // theta = f / tick_hz turns as a binary angle (2^32 a turn).
  const uint64_t theta = (static_cast<uint64_t>(frequency_q16) << 16) / tick_hz;
  // sigma dt = ln(20) / (W_t tick_hz), Q2.30.
  const int64_t sigma_dt = (kLnInverseCriterion << 16) / (int64_t{window_q16} * tick_hz);
  return gains_from_roots(theta, sigma_dt, out);
}

bool jiggle_gains_for_rate(JiggleGains built, uint32_t built_hz, uint32_t tick_hz, JiggleGains* out) {
  if (built_hz == 0 || tick_hz == 0) return false;
  if (built.stiffness <= 0 || built.stiffness > fx::kUnitOne || built.damping < 0 || built.damping >= fx::kUnitOne)
    return false;
  if (tick_hz == built_hz) return *out = built, true;
  // The roots at the built rate: r^2 = (1 - k) d, 2 r cos(theta) = (1 - k) (1 + d)
  // (products of two Q2.30 values <= 2^61, exact).
  const int64_t kept = fx::kUnitOne - built.stiffness;
  const int64_t r = fx::isqrt_u64(static_cast<uint64_t>(kept * built.damping));  // Q2.30
  if (r <= 0) return false;
  const int64_t c = (kept * (fx::kUnitOne + built.damping)) / (2 * r);  // Q2.30
  if (c <= 0 || c > fx::kUnitOne) return false;
  const int64_t s = fx::isqrt_u64(static_cast<uint64_t>((int64_t{1} << 60) - c * c));  // sin(theta), Q2.30
  const uint64_t theta = fx::atan2_angle(static_cast<int32_t>(s), static_cast<int32_t>(c));
  const int64_t sigma_dt = neg_ln_unit(r);
  // The same sigma and omega at the new rate: both per-tick quantities scale
  // by built_hz / tick_hz (rounded half up; theta < 2^30, sigma dt < 2^36 here).
  const uint64_t limit = (UINT64_MAX - tick_hz) / built_hz;  // no overflow for any u32 rates
  if (theta > limit || static_cast<uint64_t>(sigma_dt) > limit) return false;
  const auto rescale = [&](uint64_t v) { return (v * built_hz + tick_hz / 2) / tick_hz; };
  const uint64_t theta_new = rescale(theta);
  const uint64_t sigma_new = rescale(static_cast<uint64_t>(sigma_dt));
  if (sigma_new > (uint64_t{32} << fx::kUnitFracBits)) return false;  // gone within a tick
  return gains_from_roots(theta_new, static_cast<int64_t>(sigma_new), out);
}

fx::Unit coupling_stiffness(int32_t frequency_q16, uint32_t tick_hz) {
  if (frequency_q16 <= 0 || tick_hz == 0) return 0;
  // omega h = 2 pi f / tick_hz: f / tick_hz turns as a binary angle (2^32 a
  // turn), times 2 pi / 2^32 into Q2.30 (pi in Q2.30 is 3373259426).
  const uint64_t turns = (static_cast<uint64_t>(frequency_q16) << 16) / tick_hz;
  if (turns >= (uint64_t{1} << 32)) return 0;
  const int64_t omega_h = static_cast<int64_t>((turns * 3373259426u + (uint64_t{1} << 30)) >> 31);
  if (omega_h > fx::kUnitOne) return 0;
  return static_cast<fx::Unit>(fx::round_shift(omega_h * omega_h, fx::kUnitFracBits));
}

bool coupling_for_rate(fx::Unit coupling, uint32_t built_hz, uint32_t tick_hz, fx::Unit* out) {
  if (coupling <= 0 || coupling > fx::kUnitOne || built_hz == 0 || tick_hz == 0) return false;
  if (tick_hz == built_hz) return *out = coupling, true;
  // x (built_hz / tick_hz)^2 in two rounded steps; the first product is
  // below 2^62. If the second would pass 2^64, x' > 2^64 / tick_hz >= 2^32.
  uint64_t x = (static_cast<uint64_t>(coupling) * built_hz + tick_hz / 2) / tick_hz;
  if (x > (UINT64_MAX - tick_hz) / built_hz) return false;
  x = (x * built_hz + tick_hz / 2) / tick_hz;
  if (x >= (uint64_t{2} << fx::kUnitFracBits) || x == 0) return false;
  *out = static_cast<fx::Unit>(x);
  return true;
}

}  // namespace sinew::metaballs
