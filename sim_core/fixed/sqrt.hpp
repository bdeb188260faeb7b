// Integer square roots. Exact (floor) and total.
#pragma once

#include <bit>
#include <cstdint>

#include "q_formats.hpp"

namespace sinew::fx {

// floor(sqrt(v)), exact for every uint64 value: the binary restoring root,
// at most 32 rounds. The specification the faster roots are tested against;
// constexpr so tables can be built with it at compile time.
constexpr uint32_t isqrt_u64(uint64_t v) {
  uint64_t root = 0;
  uint64_t bit = uint64_t{1} << 62;
  while (bit > v) bit >>= 2;
  while (bit != 0) {
    if (v >= root + bit) {
      v -= root + bit;
      root = (root >> 1) + bit;
    } else {
      root >>= 1;
    }
    bit >>= 2;
  }
  return static_cast<uint32_t>(root);
}

// 1/sqrt(x) for x a squared norm in Q4.60 (e.g. a sum of squares of Q2.30
// components), returned in Q2.30: round(2^90 / sqrt(x)) / 2^60 scaled.
// x < 2^58 (result >= 2) saturates to INT32_MAX; x == 0 returns INT32_MAX.
Unit rsqrt_q60(uint64_t x_q60);

}  // namespace sinew::fx
