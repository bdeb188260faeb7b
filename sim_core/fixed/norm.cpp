#include "norm.hpp"

#include "rsqrt_fast.hpp"
#include "scalar.hpp"
#include "sqrt.hpp"
#include "wide.hpp"

namespace sinew::fx {

NormDivisor norm_divisor(const int32_t* components, int count) {
  uint64_t m = 0;
  for (int i = 0; i < count; ++i) {
    const uint64_t a = magnitude(components[i]);
    if (a > m) m = a;
  }
  if (m == 0) return {0, 0};
  int shift = 0;
  if (m >= (uint64_t{1} << 30)) {
    while (shift > -2 && (m >> -shift) >= (uint64_t{1} << 30)) --shift;
  } else {
    while ((m << (shift + 1)) < (uint64_t{1} << 30)) ++shift;
  }
  uint64_t n2 = 0;  // < 4 * 2^60
  for (int i = 0; i < count; ++i) {
    int64_t c = shift >= 0 ? int64_t{components[i]} * (int64_t{1} << shift) : round_shift(components[i], -shift);
    c = clamp_i64(c, -(int64_t{1} << 30) + 1, (int64_t{1} << 30) - 1);  // keeps n2 << 2 < 2^64
    n2 += static_cast<uint64_t>(c * c);
  }
  const uint64_t n = n2 << 2;  // < 2^64: sqrt gives 2 * norm
  uint64_t s = isqrt_fast(n);
  if (n - s * s > s) ++s;  // round to nearest
  return {static_cast<int64_t>(s), shift};
}

int32_t divide_by_norm(int32_t value, const NormDivisor& d) {
  if (d.length == 0) return 0;
  // value * 2^(30 + shift) / |scaled| = value * 2^(31 + shift) / length.
  const int e = 31 + d.shift;
  if (magnitude(value) >= (uint64_t{1} << (61 - e))) return value < 0 ? INT32_MIN : INT32_MAX;
  return sat_i32(div_round(int64_t{value} * (int64_t{1} << e), d.length));
}

}  // namespace sinew::fx
