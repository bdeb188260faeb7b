#include "sqrt.hpp"

#include "scalar.hpp"

namespace sinew::fx {

uint32_t isqrt_u64(uint64_t v) {
  // Binary restoring square root: at most 32 iterations, exact floor.
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

Unit rsqrt_q60(uint64_t x_q60) {
  if (x_q60 < (uint64_t{1} << 58)) return INT32_MAX;
  if (x_q60 < (uint64_t{1} << 62)) {
    // sqrt in Q31 (one extra bit): isqrt(x * 2^2); 1/sqrt in Q30 = 2^61 / s.
    const uint64_t s = isqrt_u64(x_q60 << 2);
    return sat_i32(static_cast<int64_t>(((uint64_t{1} << 61) + s / 2) / s));
  }
  const uint64_t s = isqrt_u64(x_q60);  // Q30
  return sat_i32(static_cast<int64_t>(((uint64_t{1} << 60) + s / 2) / s));
}

}  // namespace sinew::fx
