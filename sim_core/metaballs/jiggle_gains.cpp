#include "jiggle_gains.hpp"

#include "sim_core/fixed/scalar.hpp"
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

bool jiggle_gains(int32_t frequency_q16, int32_t window_q16, uint32_t tick_hz, JiggleGains* out) {
  if (frequency_q16 <= 0 || window_q16 <= 0 || tick_hz == 0) return false;
  // theta = f / tick_hz turns as a binary angle (2^32 a turn).
  const uint64_t theta = (static_cast<uint64_t>(frequency_q16) << 16) / tick_hz;
  if (theta >= fx::kQuarterTurn) return false;
  // sigma dt = ln(20) / (W_t tick_hz), Q2.30.
  const int64_t sigma_dt = (kLnInverseCriterion << 16) / (int64_t{window_q16} * tick_hz);
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

}  // namespace sinew::metaballs
