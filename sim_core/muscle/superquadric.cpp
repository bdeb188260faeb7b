#include "superquadric.hpp"

#include "sim_core/fixed/log_exp.hpp"
#include "sim_core/fixed/vec3.hpp"
#include "sim_core/fixed/wide.hpp"

namespace sinew::muscle {
namespace {

constexpr int64_t kOne = int64_t{1} << fx::kUnitFracBits;
constexpr int64_t kOutsideBox = int64_t{4} << fx::kUnitFracBits;
constexpr int kRatioFrac = 58, kInverseFrac = 60;

// A Q16.16 power times a Q30 logarithm, in Q30 (|p| <= 2^20, |log| < 2^51).
int64_t times_power(int64_t p_q16, int64_t log_q30) { return fx::mul_shift_round(p_q16, log_q30, 16); }

// log2(2^a + 2^b) in Q30: the larger plus log2(1 + 2^-(difference)), the
// small term in Q62 (exact to 2^-62 relative), one rounding to Q30.
int64_t log2_sum(int64_t a, int64_t b) {
  const int64_t hi = a > b ? a : b, lo = a > b ? b : a;
  const uint64_t small = static_cast<uint64_t>(fx::exp2_fixed(lo - hi, 62));  // <= 2^62
  return hi + fx::log2_q30((uint64_t{1} << 62) + small, 62);
}

// round(n 2^(a + b) / d) for 0 < n, d: n 2^a / d exactly (n 2^a < 2^63),
// then the remainder's 2^b (r 2^b < 2^63; the quotient's q 2^b too).
int64_t scaled_quotient(int64_t n, int a, int b, int64_t d) {
  const int64_t q = (n << a) / d, r = (n << a) % d;
  return (q << b) + fx::div_round(r << b, d);
}

}  // namespace

void superquadric_prepare(PrimitiveFrame* f) {
  SuperquadricTerms& t = f->superquadric;
  // Validated powers are in [1, 16]; anything else is clamped so the terms stay defined.
  const int64_t pxy = fx::clamp_i64(t.power_xy, kMinPower, kMaxPower);
  const int64_t pz = fx::clamp_i64(t.power_z, kMinPower, kMaxPower);
  t.ratio = scaled_quotient(pz, 42, kRatioFrac - 42, pxy);                 // <= 16 2^58 = 2^62
  t.inverse_power_z = scaled_quotient(1, 62, kInverseFrac + 16 - 62, pz);  // <= 2^60
  t.log2_power_z = fx::log2_q30(static_cast<uint64_t>(pz), 16);
  int64_t emax = 1;
  for (int i = 0; i < 3; ++i) {
    const int64_t e = f->extent[i];
    t.log2_extent[i] = e > 0 ? fx::log2_q30(static_cast<uint64_t>(e), 0) : fx::kLog2OfZero;
    if (e > emax) emax = e;
  }
  t.log2_emax = fx::log2_q30(static_cast<uint64_t>(emax), 0);
}

SuperquadricEval superquadric_eval(const PrimitiveFrame& f, const int64_t local[3]) {
  const SuperquadricTerms& t = f.superquadric;
  const int64_t pxy = fx::clamp_i64(t.power_xy, kMinPower, kMaxPower);
  const int64_t pz = fx::clamp_i64(t.power_z, kMinPower, kMaxPower);
  SuperquadricEval e;
  e.log2_terms[0] = e.log2_terms[1] = fx::kLog2OfZero;
  bool has[3];
  int64_t lq[3];  // log2 |q_i|, Q30
  for (int i = 0; i < 3; ++i) {
    has[i] = local[i] != 0;
    lq[i] = has[i] ? fx::log2_q30(fx::magnitude(local[i]), 0) - t.log2_extent[i] : 0;
  }
  if (!has[0] && !has[1] && !has[2]) return e;  // the centre: F = 0, no gradient
  // log2 S, S = |qx|^p_xy + |qy|^p_xy; F = S^e + |qz|^p_z.
  const bool has_s = has[0] || has[1];
  int64_t ls = 0;
  if (has[0] && has[1]) {
    ls = log2_sum(times_power(pxy, lq[0]), times_power(pxy, lq[1]));
  } else if (has_s) {
    ls = times_power(pxy, has[0] ? lq[0] : lq[1]);
  }
  if (has_s) e.log2_terms[0] = fx::mul_shift_round(t.ratio, ls, kRatioFrac);
  if (has[2]) e.log2_terms[1] = times_power(pz, lq[2]);
  // Each term at most 2^16 inside the box (S < 2, e <= 16; Z < 1): no overflow.
  const int64_t value =
      fx::exp2_fixed(e.log2_terms[0], fx::kUnitFracBits) + fx::exp2_fixed(e.log2_terms[1], fx::kUnitFracBits);
  e.value = value < kOutsideBox ? value : kOutsideBox;
  e.inside = e.value < kOne;
  // Gradient exponents L_i (header), each against the largest.
  const int64_t scale_xy = fx::mul_shift_round(t.ratio - (int64_t{1} << kRatioFrac), ls, kRatioFrac);
  int64_t l[3] = {};
  int64_t top = INT64_MIN;
  for (int i = 0; i < 3; ++i) {
    if (!has[i]) continue;
    const int64_t axis = t.log2_emax - t.log2_extent[i];
    l[i] = i < 2 ? scale_xy + times_power(pxy - (1 << 16), lq[i]) + axis : times_power(pz - (1 << 16), lq[2]) + axis;
    if (l[i] > top) top = l[i];
  }
  for (int i = 0; i < 3; ++i) {
    if (!has[i]) continue;
    const int64_t m = l[i] == top ? kOne : fx::exp2_fixed(l[i] - top, fx::kUnitFracBits);  // (0, 2^30]
    e.g[i] = local[i] < 0 ? -m : m;
  }
  e.log2_largest = top;
  e.g_length = fx::length({static_cast<int32_t>(e.g[0]), static_cast<int32_t>(e.g[1]), static_cast<int32_t>(e.g[2])});
  // |grad F| emax = p_z 2^top |g| / 2^30 in Q20; the power of two capped at
  // 2^33 (gradient_length saturates at 2^31 anyway) keeps the product in range.
  const int64_t scale = fx::exp2_fixed(t.log2_power_z + top, fx::kLenFracBits);
  const int64_t capped = scale < (int64_t{1} << 33) ? scale : int64_t{1} << 33;
  e.gradient_length = fx::sat_i32(fx::mul_shift_round(capped, e.g_length, fx::kUnitFracBits));
  return e;
}

int64_t superquadric_newton_step(const PrimitiveFrame& f, const SuperquadricEval& e) {
  const SuperquadricTerms& t = f.superquadric;
  const bool both = e.log2_terms[0] != fx::kLog2OfZero && e.log2_terms[1] != fx::kLog2OfZero;
  const int64_t lf = both ? log2_sum(e.log2_terms[0], e.log2_terms[1])
                          : (e.log2_terms[0] != fx::kLog2OfZero ? e.log2_terms[0] : e.log2_terms[1]);  // log2 F
  const int64_t lg = fx::mul_shift_round(lf, t.inverse_power_z, kInverseFrac);                         // log2 G
  const int64_t gap = kOne - fx::exp2_fixed(lg, fx::kUnitFracBits);                                    // 1 - G, Q30
  if (gap <= 0 || e.g_length == 0) return 0;
  // log2 of p_z (1 - G) F emax / (G |grad F| emax), in Len LSBs, with
  // |grad F| emax = p_z 2^top |g| / 2^30.
  const int64_t ld = fx::log2_q30(static_cast<uint64_t>(gap), fx::kUnitFracBits) + lf + t.log2_emax - lg -
                     e.log2_largest - fx::log2_q30(e.g_length, fx::kUnitFracBits);
  return fx::exp2_fixed(ld, 0);
}

}  // namespace sinew::muscle
