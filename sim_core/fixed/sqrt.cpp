#include "sqrt.hpp"

#include "rsqrt_fast.hpp"
#include "scalar.hpp"

namespace sinew::fx {

Unit rsqrt_q60(uint64_t x_q60) {
  if (x_q60 < (uint64_t{1} << 58)) return INT32_MAX;
  if (x_q60 < (uint64_t{1} << 62)) {
    // sqrt in Q31 (one extra bit): isqrt(x * 2^2); 1/sqrt in Q30 = 2^61 / s.
    const uint64_t s = isqrt_fast(x_q60 << 2);
    return sat_i32(static_cast<int64_t>(((uint64_t{1} << 61) + s / 2) / s));
  }
  const uint64_t s = isqrt_fast(x_q60);  // Q30
  return sat_i32(static_cast<int64_t>(((uint64_t{1} << 60) + s / 2) / s));
}

}  // namespace sinew::fx
