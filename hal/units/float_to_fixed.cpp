#include "float_to_fixed.hpp"

#include <cmath>
#include <numbers>

#include "double_bits.hpp"
#include "radian_turns.hpp"
#include "sim_core/fixed/q_formats.hpp"
#include "sim_core/fixed/scalar.hpp"

namespace sinew::units {

namespace {

using detail::double_bits;
using detail::DoubleBits;

constexpr FixedResult kNaNResult{0, kNotFinite};

// round_half_up(x * 2^frac_bits), saturated to int32. Exact: |x| is an
// integer mantissa < 2^53 times 2^exponent, so the scaled value is that
// mantissa shifted by exponent + frac_bits (any int64 shift).
FixedResult scale_to_fixed(double x, int64_t frac_bits) {
  const DoubleBits d = double_bits(x);
  if (d.nan) return kNaNResult;
  const FixedResult low{INT32_MIN, kClamped};
  const FixedResult high{INT32_MAX, kClamped};
  if (!d.finite)
    return d.negative ? FixedResult{INT32_MIN, kNotFinite | kClamped} : FixedResult{INT32_MAX, kNotFinite | kClamped};
  if (d.mantissa == 0) return {0, kOk};  // +0.0 and -0.0

  const int64_t shift = d.exponent + frac_bits;
  const int64_t signed_mantissa = d.negative ? -static_cast<int64_t>(d.mantissa) : static_cast<int64_t>(d.mantissa);
  int64_t scaled = 0;
  ConversionFlags flags = kOk;
  if (shift >= 0) {
    // Integer result: at least 2^32 in magnitude once the mantissa shifted
    // past bit 31.
    if (shift >= 32 || (d.mantissa >> (32 - shift)) != 0) return d.negative ? low : high;
    scaled = signed_mantissa * (int64_t{1} << shift);
  } else if (shift < -62) {
    // |x * 2^frac_bits| < 2^53 / 2^63: rounds to 0 from either side.
    return {0, kRounded};
  } else {
    const int s = static_cast<int>(-shift);
    scaled = fx::round_shift(signed_mantissa, s);  // half up; |mantissa| < 2^53, no overflow
    if ((d.mantissa & ((uint64_t{1} << s) - 1)) != 0) flags = kRounded;
  }
  if (scaled > INT32_MAX) return high;
  if (scaled < INT32_MIN) return low;
  return {static_cast<int32_t>(scaled), flags};
}

// int64 -> binary angle, modulo 2^32 (well defined for unsigned types).
uint32_t wrap_to_angle(int64_t steps) { return static_cast<uint32_t>(static_cast<uint64_t>(steps)); }

}  // namespace

FixedResult to_fixed(double x, int32_t frac_bits) { return scale_to_fixed(x, frac_bits); }

FixedResult to_unit(double x) { return scale_to_fixed(x, fx::kUnitFracBits); }

FixedResult to_lin(double x) { return scale_to_fixed(x, fx::kLinFracBits); }

FixedResult to_len(double x, int32_t length_exponent) {
  return scale_to_fixed(x, int64_t{fx::kLenFracBits} - length_exponent);
}

AngleResult angle_from_degrees(double deg) {
  const DoubleBits in = double_bits(deg);
  if (!in.finite) return {0, kNotFinite};
  // fmod is exact (its result is representable and IEEE requires it exact),
  // and whole turns do not change the angle.
  const DoubleBits d = double_bits(std::fmod(deg, 360.0));
  if (d.mantissa == 0) return {0, kOk};
  // steps = r * 2^32 / 360 = mantissa * 2^(exponent + 29) / 45. |r| < 360
  // makes exponent + 29 <= -15: divide by 45 * 2^j, j >= 15, rounding half up.
  const int64_t j = -(int64_t{d.exponent} + 29);
  if (j > 57) return {0, kRounded};          // |steps| < 2^53 / (45 * 2^58) < 1/2
  const int64_t divisor = int64_t{45} << j;  // < 2^63 for j <= 57
  const int64_t n = d.negative ? -static_cast<int64_t>(d.mantissa) : static_cast<int64_t>(d.mantissa);
  const int64_t steps = fx::floor_div(n + divisor / 2, divisor);
  const bool exact = static_cast<int64_t>(d.mantissa) % divisor == 0;
  return {wrap_to_angle(steps), exact ? kOk : kRounded};
}

FixedResult signed_angle_from_degrees(double deg) {
  const AngleResult a = angle_from_degrees(deg);
  if (a.has(kNotFinite)) return {0, kNotFinite};
  // The half turn is -180 only when the input (mod 360, which keeps its
  // sign) is negative; a positive one at or just below +180 rounds onto it.
  if (a.value == 0x80000000u && std::fmod(deg, 360.0) > 0.0) return {INT32_MAX, kClamped};
  return {static_cast<int32_t>(a.value), a.flags};
}

AngleResult angle_from_radians(double rad) {
  const DoubleBits d = double_bits(rad);
  if (!d.finite) return {0, kNotFinite};
  if (d.mantissa == 0) return {0, kOk};
  detail::TurnFraction t = detail::turns_of_radians(d.mantissa, d.exponent);
  if (d.negative) {  // frac(-v) = 2^192 - frac(v), modulo 2^192
    t.word[0] = ~t.word[0];
    t.word[1] = ~t.word[1];
    t.word[2] = ~t.word[2] + 1;
    if (t.word[2] == 0 && ++t.word[1] == 0) ++t.word[0];
  }
  // The top 32 bits are whole steps; bit 31 of the word is the half. The
  // 160 bits below are never exactly a tie (pi is irrational) and the
  // truncation (< 2^-107 step) is far below how close a double comes to one.
  const uint64_t top = t.word[0];
  return {static_cast<uint32_t>((top >> 32) + ((top >> 31) & 1u)), kRounded};
}

double fixed_to_double(int32_t value, int32_t frac_bits) {
  return std::ldexp(static_cast<double>(value), -static_cast<int>(fx::clamp_i64(frac_bits, -1000, 1000)));
}

double unit_to_double(int32_t unit) { return std::ldexp(static_cast<double>(unit), -fx::kUnitFracBits); }

double lin_to_double(int32_t lin) { return std::ldexp(static_cast<double>(lin), -fx::kLinFracBits); }

double len_to_double(int32_t len, int32_t length_exponent) {
  // Beyond +-2100 the result is 0 or inf anyway; the clamp keeps the int
  // argument of ldexp from overflowing.
  const int64_t e = fx::clamp_i64(int64_t{length_exponent} - fx::kLenFracBits, -2100, 2100);
  return std::ldexp(static_cast<double>(len), static_cast<int>(e));
}

// The int32 view of an angle is fx::angle_signed's: [-half turn, half turn).
double angle_to_degrees(uint32_t angle) {
  // 360 * s < 2^41 and the scaling by 2^-32 are both exact.
  return static_cast<double>(static_cast<int32_t>(angle)) * 360.0 * 0x1p-32;
}

double angle_to_radians(uint32_t angle) {
  return static_cast<double>(static_cast<int32_t>(angle)) * (2.0 * std::numbers::pi * 0x1p-32);
}

}  // namespace sinew::units
