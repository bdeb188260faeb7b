// Saturating 64-bit helpers for the bar-net solve: a rounded 64x64 product
// shift that clamps instead of overflowing (fx::mul_shift_round requires the
// result to fit), and a symmetric clamp of solve vectors.
#pragma once

#include <cstdint>

#include "sim_core/fixed/scalar.hpp"
#include "sim_core/fixed/wide.hpp"

namespace sinew::barnet {

// Solve vectors are kept within +-2^61 so that a sum of two never overflows
// and a product with a Q2.30 factor (|L| < 2) shifted by 30 stays below 2^62.
inline constexpr int64_t kVectorLimit = int64_t{1} << 61;

inline int64_t clamp_vector(int64_t v, fx::Saturation& sat) {
  const int64_t r = fx::clamp_i64(v, -kVectorLimit, kVectorLimit);
  sat.events += static_cast<uint32_t>(r != v);
  return r;
}

// round_half_up(a * b / 2^s), 1 <= s <= 62, clamped to +-kVectorLimit.
inline int64_t mul_shift_round_sat(int64_t a, int64_t b, int s, fx::Saturation& sat) {
  const bool negative = (a < 0) != (b < 0);
  fx::U128 p = fx::mul_u64(fx::magnitude(a), fx::magnitude(b));
  const uint64_t half = (uint64_t{1} << (s - 1)) - (negative ? 1u : 0u);
  const uint64_t lo = p.lo + half;
  p.hi += static_cast<uint64_t>(lo < p.lo);
  // The shifted magnitude fits in 64 bits iff hi < 2^s; then it must not
  // exceed the vector limit.
  if ((p.hi >> s) != 0) {
    ++sat.events;
    return negative ? -kVectorLimit : kVectorLimit;
  }
  const uint64_t m = (p.hi << (64 - s)) | (lo >> s);
  if (m > static_cast<uint64_t>(kVectorLimit)) {
    ++sat.events;
    return negative ? -kVectorLimit : kVectorLimit;
  }
  return negative ? -static_cast<int64_t>(m) : static_cast<int64_t>(m);
}

// mul_shift_round_sat(l, v, 30, sat) for a Q2.30 factor entry l (int32) and
// a solve vector value v (|v| <= kVectorLimit: every value the factor and the
// solve multiply is a clamped vector value), bit for bit, saturation count
// included, with two plain 64-bit products and no branch: with v = vh 2^32 +
// vl (vh = v >> 32, |vh| <= 2^29; vl = v mod 2^32, unsigned),
// floor((l v + 2^29) / 2^30) = 4 l vh + floor((l vl + 2^29) / 2^30), because
// 2^32 is a multiple of 2^30; |4 l vh| <= 2^62 and |l vl| < 2^63 - 2^32, so
// both terms fit int64. That floor is round half up of the signed product,
// which mul_shift_round_sat forms from the magnitudes. The skyline factor and
// solve spend most of their time here (ldlt_skyline.cpp).
inline int64_t mul_l30_round_sat(int32_t l, int64_t v, fx::Saturation& sat) {
  const int64_t vh = v >> 32;
  const int64_t vl = static_cast<int64_t>(static_cast<uint64_t>(v) & 0xFFFFFFFFu);
  const int64_t p = 4 * (int64_t{l} * vh) + ((int64_t{l} * vl + (int64_t{1} << 29)) >> 30);
  return clamp_vector(p, sat);
}

// mul_l30_round_sat without its clamp, for |l| <= 2^30: then |l v| / 2^30 <=
// |v| <= kVectorLimit, so the clamp never fires and counts nothing.
inline int64_t mul_l30_unit_bounded(int32_t l, int64_t v) {
  const int64_t vh = v >> 32;
  const int64_t vl = static_cast<int64_t>(static_cast<uint64_t>(v) & 0xFFFFFFFFu);
  return 4 * (int64_t{l} * vh) + ((int64_t{l} * vl + (int64_t{1} << 29)) >> 30);
}

}  // namespace sinew::barnet
