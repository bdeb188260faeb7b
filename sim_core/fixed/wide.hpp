// Portable 64x64 -> 128-bit products (no __int128: armhf has none), used by
// the high-precision kernels of trig and by range-safe accumulations.
#pragma once

#include <cstdint>

namespace sinew::fx {

struct U128 {
  uint64_t hi;
  uint64_t lo;
};

#if defined(__SIZEOF_INT128__)
// One hardware multiply where the compiler has a 128-bit type (x86-64,
// aarch64); the same exact product as the portable form below (armhf).
__extension__ typedef unsigned __int128 NativeU128;
inline constexpr U128 mul_u64(uint64_t a, uint64_t b) {
  const NativeU128 p = static_cast<NativeU128>(a) * b;
  return U128{static_cast<uint64_t>(p >> 64), static_cast<uint64_t>(p)};
}
#else
inline constexpr U128 mul_u64(uint64_t a, uint64_t b) {
  const uint64_t a_lo = a & 0xFFFFFFFFu, a_hi = a >> 32;
  const uint64_t b_lo = b & 0xFFFFFFFFu, b_hi = b >> 32;
  const uint64_t p0 = a_lo * b_lo, p1 = a_lo * b_hi, p2 = a_hi * b_lo, p3 = a_hi * b_hi;
  const uint64_t mid = (p0 >> 32) + (p1 & 0xFFFFFFFFu) + (p2 & 0xFFFFFFFFu);
  return U128{p3 + (p1 >> 32) + (p2 >> 32) + (mid >> 32), (mid << 32) | (p0 & 0xFFFFFFFFu)};
}
#endif

inline constexpr uint64_t magnitude(int64_t v) {
  return v < 0 ? uint64_t{0} - static_cast<uint64_t>(v) : static_cast<uint64_t>(v);
}

namespace detail {

// mul_shift_round below on the magnitudes' 128-bit product: the form every
// target has (armhf has no 128-bit type).
inline constexpr int64_t mul_shift_round_u128(int64_t a, int64_t b, int s) {
  const bool negative = (a < 0) != (b < 0);
  U128 p = mul_u64(magnitude(a), magnitude(b));
  // Half up on the signed value: +half on magnitudes of positive results,
  // +half-1 on magnitudes of negative ones (so -x.5 rounds to -x).
  const uint64_t half = (uint64_t{1} << (s - 1)) - (negative ? 1u : 0u);
  const uint64_t lo = p.lo + half;
  p.hi += static_cast<uint64_t>(lo < p.lo);
  p.lo = lo;
  const uint64_t m = (p.hi << (64 - s)) | (p.lo >> s);
  return static_cast<int64_t>(negative ? uint64_t{0} - m : m);  // modular, defined in C++20
}

}  // namespace detail

// round_half_up(a * b / 2^s) for 1 <= s <= 63. Precondition: the result fits
// in int64 (callers keep |a*b| < 2^(62+s)); outside it, the low 64 bits.
inline constexpr int64_t mul_shift_round(int64_t a, int64_t b, int s) {
#if defined(__SIZEOF_INT128__)
  // The signed product's floor((a b + 2^(s-1)) / 2^s) equals the
  // magnitudes' rounding of detail::mul_shift_round_u128 bit for bit (for a
  // negative product, -floor((|ab| + 2^(s-1) - 1) / 2^s) = floor((ab +
  // 2^(s-1)) / 2^s)), in one multiply and a shift.
  __extension__ typedef __int128 NativeI128;
  const NativeI128 p = static_cast<NativeI128>(a) * b;  // |p| <= 2^126
  return static_cast<int64_t>((p >> s) + ((p >> (s - 1)) & 1));
#else
  return detail::mul_shift_round_u128(a, b, s);
#endif
}

}  // namespace sinew::fx
