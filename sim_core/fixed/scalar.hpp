// Scalar fixed-point operations: rounding, saturation, products, division.
// All functions are total (defined for every input) and free of UB.
#pragma once

#include <cstdint>

#include "q_formats.hpp"

namespace sinew::fx {

// Counts values clamped by saturating narrowings. Owned by whoever runs a step.
struct Saturation {
  uint32_t events = 0;
};

inline constexpr int32_t sat_i32(int64_t v) {
  return v > INT32_MAX ? INT32_MAX : (v < INT32_MIN ? INT32_MIN : static_cast<int32_t>(v));
}

inline constexpr int32_t sat_i32(int64_t v, Saturation& sat) {
  const int32_t r = sat_i32(v);
  sat.events += static_cast<uint32_t>(r != v);
  return r;
}

inline constexpr int64_t clamp_i64(int64_t v, int64_t lo, int64_t hi) { return v < lo ? lo : (v > hi ? hi : v); }

// Saturating 64-bit addition (used where operands come from unchecked data).
// The sum overflows only toward b's sign, so that sign picks the limit; the
// overflow test is the CPU's own flag (one add and a conditional move).
inline constexpr int64_t add_sat_i64(int64_t a, int64_t b) {
  int64_t r = 0;
  if (__builtin_add_overflow(a, b, &r)) return b > 0 ? INT64_MAX : INT64_MIN;
  return r;
}

// Round half up: (v + 2^(s-1)) >> s, for 1 <= s <= 62, total over int64.
// Computed as (v >> s) + bit (s - 1) of v, which is the same value without
// forming v + 2^(s-1): a saturated sum (INT64_MAX from add_sat_i64) rounds
// without overflowing, and every other input gives the same bits as before.
inline constexpr int64_t round_shift(int64_t v, int s) { return (v >> s) + ((v >> (s - 1)) & 1); }

// Q2.30 x Q2.30 -> Q2.30. Only (-2)*(-2) saturates.
inline constexpr Unit mul_unit(Unit a, Unit b) { return sat_i32(round_shift(int64_t{a} * b, kUnitFracBits)); }

// Any Q(m.n) x Q2.30 -> Q(m.n): scales a value by a unit quantity.
inline constexpr int32_t mul_by_unit(int32_t v, Unit u) { return sat_i32(round_shift(int64_t{v} * u, kUnitFracBits)); }

// Any Q(m.n) x Q8.24 -> Q(m.n).
inline constexpr int32_t mul_by_lin(int32_t v, Lin l) { return sat_i32(round_shift(int64_t{v} * l, kLinFracBits)); }

// -v, with -INT32_MIN saturating to INT32_MAX.
inline constexpr int32_t neg_sat(int32_t v) { return v == INT32_MIN ? INT32_MAX : -v; }

inline constexpr int32_t add_sat(int32_t a, int32_t b) { return sat_i32(int64_t{a} + b); }
inline constexpr int32_t sub_sat(int32_t a, int32_t b) { return sat_i32(int64_t{a} - b); }

// Floor division for d > 0 (C++ truncates toward zero).
inline constexpr int64_t floor_div(int64_t n, int64_t d) {
  const int64_t q = n / d;
  return (n % d != 0 && n < 0) ? q - 1 : q;
}

// n / d rounded half up (ties toward +inf), total over int64: the quotient
// and remainder are taken first and the remainder compared with d in
// unsigned magnitudes, so no 2n + d is formed (the former precondition |n| <
// 2^62 is gone; inside it the result is the same). The one quotient beyond
// int64, INT64_MIN / -1, saturates to INT64_MAX. d == 0 returns 0
// (documented; callers check denominators they can't prove).
inline constexpr int64_t div_round(int64_t n, int64_t d) {
  if (d == 0) return 0;
  if (d == -1) return n == INT64_MIN ? INT64_MAX : -n;
  const int64_t q = n / d, r = n % d;
  if (r == 0) return q;
  const uint64_t r2 = 2 * (r < 0 ? uint64_t{0} - static_cast<uint64_t>(r) : static_cast<uint64_t>(r));
  const uint64_t dm = d < 0 ? uint64_t{0} - static_cast<uint64_t>(d) : static_cast<uint64_t>(d);
  // |d| >= 2 here, so |q| <= 2^62 and q +- 1 cannot overflow.
  if ((r < 0) == (d < 0)) return r2 >= dm ? q + 1 : q;  // positive fraction: half rounds up
  return r2 > dm ? q - 1 : q;                           // negative fraction: half rounds up (toward q)
}

// Converts between fractional-bit counts with rounding (right) or saturation (left).
inline constexpr int32_t requantize(int32_t v, int from_frac, int to_frac) {
  if (from_frac == to_frac) return v;
  if (from_frac > to_frac) return sat_i32(round_shift(v, from_frac - to_frac));
  return sat_i32(int64_t{v} * (int64_t{1} << (to_frac - from_frac)));
}

}  // namespace sinew::fx
