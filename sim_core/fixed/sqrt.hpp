// Integer square roots. Exact (floor) and total.
#pragma once

#include <bit>
#include <cstdint>

#include "q_formats.hpp"

namespace sinew::fx {

// floor(sqrt(v)), exact for every uint64 value.
uint32_t isqrt_u64(uint64_t v);

// 1/sqrt(x) for x a squared norm in Q4.60 (e.g. a sum of squares of Q2.30
// components), returned in Q2.30: round(2^90 / sqrt(x)) / 2^60 scaled.
// x < 2^58 (result >= 2) saturates to INT32_MAX; x == 0 returns INT32_MAX.
Unit rsqrt_q60(uint64_t x_q60);

// Exact floor(sqrt(v)) started from a nearby guess (the elastic skin takes
// an edge length per edge per round, close to its rest length): so Newton from it converges in two or three divisions
// instead of the 32 rounds of the bitwise root. Same result as isqrt_u64 for every input (it falls back to it after at
// most 9 divisions).
inline uint32_t isqrt_hinted(uint64_t v, uint64_t hint) {
  if (v == 0) return 0;
  uint64_t x = hint;
  // A hint off by more than a factor 2 (a crushed or torn edge) is replaced
  // by 2^ceil(bits / 2), within a factor 2 of the root as well.
  if (x == 0 || x >= (uint64_t{1} << 32) || x * x / 4 > v || x * x < v / 4)
    x = uint64_t{1} << ((std::bit_width(v) + 1) / 2);
  // One Newton step from any positive x lands at or above floor(sqrt(v))
  // (AM-GM survives the floor divisions); from there Newton decreases
  // monotonically to floor(sqrt(v)) exactly.
  x = x / 2 + v / x / 2 + ((x & 1) + ((v / x) & 1)) / 2;
  for (int i = 0; i < 8; ++i) {
    const uint64_t y = x / 2 + v / x / 2 + ((x & 1) + ((v / x) & 1)) / 2;  // (x + v / x) / 2 without overflow
    if (y >= x) return static_cast<uint32_t>(x);
    x = y;
  }
  return isqrt_u64(v);
}

}  // namespace sinew::fx
