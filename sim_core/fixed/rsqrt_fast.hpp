// Division-free reciprocal square root for per-vertex normalisation: a
// 192-entry seed table (built at compile time with exact integer sqrt) and
// two Newton steps y <- y (3 - v y^2) / 2, all in 64-bit integers. Pure
// integer, so bit-identical everywhere; about 1e-9 relative error (measured in
// tests/sim_core/fixed, docs/numerics.md).
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>

#include "q_formats.hpp"
#include "sqrt.hpp"
#include "vec3.hpp"
#include "wide.hpp"

namespace sinew::fx {

namespace detail {

// Seed for v in [1, 4) split into 192 steps of 1/64: Q30 of 1/sqrt(midpoint),
// midpoint (129 + 2i) / 128: sqrt(2^67 / (129 + 2i)).
constexpr std::array<uint32_t, 192> make_rsqrt_seed() {
  std::array<uint32_t, 192> t{};
  for (size_t i = 0; i < t.size(); ++i)
    t[i] = static_cast<uint32_t>(isqrt_u64(32 * ((uint64_t{1} << 62) / (129 + 2 * uint64_t{i}))));
  return t;
}

inline constexpr std::array<uint32_t, 192> kRsqrtSeed = make_rsqrt_seed();

}  // namespace detail

// For x > 0 returns y and half_shift with 1/sqrt(x) = y * 2^(half_shift - 61)
// (y in Q30 of 1/sqrt(v), v = x * 2^(2 half_shift) / 2^62 in [1, 4)).
struct RsqrtResult {
  int64_t y;
  int half_shift;
};

inline RsqrtResult rsqrt_fast(uint64_t x) {
  const int s = std::countl_zero(x) & ~1;                               // even, so sqrt scales by 2^(s/2)
  const uint64_t m = x << s;                                            // in [2^62, 2^64)
  int64_t y = detail::kRsqrtSeed[static_cast<size_t>((m >> 56) - 64)];  // 0..191
  const int64_t v = static_cast<int64_t>(m >> 32);                      // Q30, [2^30, 2^32)
  for (int i = 0; i < 2; ++i) {
    const int64_t y2 = (y * y) >> 30;
    const int64_t vy2 = (v * y2) >> 30;
    y = (y * ((int64_t{3} << 30) - vy2)) >> 31;
  }
  return {y, s / 2};
}

// floor(sqrt(v)), exact for every uint64 value like isqrt_u64, without a
// division: v times the reciprocal root above (about 1e-9 relative, so
// within a few units of the root for any v < 2^64), then settled with exact
// integer squares. Should the estimate ever be more than 8 off, the bitwise
// root decides, so the result never depends on the estimate's accuracy.
inline uint32_t isqrt_fast(uint64_t v) {
  if (v == 0) return 0;
  const RsqrtResult r = rsqrt_fast(v);
  // sqrt(v) = v / sqrt(v) = v * y * 2^(half_shift - 61); y < 2^31, so the
  // product is < 2^95 and the shift (30..61) brings it below 2^65.
  const U128 p = mul_u64(v, static_cast<uint64_t>(r.y));
  const int shift = 61 - r.half_shift;
  const uint64_t hi_part = p.hi >> shift;
  uint64_t x = (p.hi << (64 - shift)) | (p.lo >> shift);
  if (hi_part != 0 || x > 0xFFFFFFFFu) x = 0xFFFFFFFFu;
  for (int i = 0; i < 8 && x * x > v; ++i) --x;  // x <= 2^32 - 1: x * x fits
  for (int i = 0; i < 8 && x < 0xFFFFFFFFu && (x + 1) * (x + 1) <= v; ++i) ++x;
  if (x * x > v || (x < 0xFFFFFFFFu && (x + 1) * (x + 1) <= v)) return isqrt_u64(v);
  return static_cast<uint32_t>(x);
}

// Unit direction (Q2.30) of any int32 vector, division-free; zero vector ->
// zero and false. Direction is exact to rounding; length within ~4 LSB of 1.
inline bool normalize_fast(Vec3 v, Vec3* out) {
  const int64_t x = v.x, y = v.y, z = v.z;
  const uint64_t n2 = static_cast<uint64_t>(x * x) + static_cast<uint64_t>(y * y) + static_cast<uint64_t>(z * z);
  if (n2 == 0) {
    *out = {0, 0, 0};
    return false;
  }
  const RsqrtResult r = rsqrt_fast(n2);
  // c / sqrt(n2) in Q30 = c * y * 2^(half_shift - 61) * 2^30 = (c * y) >> (31 - half_shift).
  const int shift = 31 - r.half_shift;
  const auto scale = [&](int64_t c) { return sat_i32(shift > 0 ? round_shift(c * r.y, shift) : c * r.y); };
  *out = {scale(x), scale(y), scale(z)};
  return true;
}

}  // namespace sinew::fx
