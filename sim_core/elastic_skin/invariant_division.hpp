// Rounded division by a divisor that stays fixed across many calls (a
// tick's substep rate and substep count, the implicit-dashpot denominator
// most skin vertices share): one division when the divisor is set, then a
// 64x64 -> 128-bit product and at most two corrections per call. The result
// is fx::div_round's, bit for bit, for every int64 numerator and d > 0.
#pragma once

#include <cstdint>

#include "sim_core/fixed/scalar.hpp"
#include "sim_core/fixed/wide.hpp"

namespace sinew::elastic_skin {

struct InvariantDivisor {
  uint64_t d = 1;           // the divisor, > 0
  uint64_t m = UINT64_MAX;  // floor((2^64 - 1) / d)
};

// d > 0 (callers pass validated, positive divisors).
inline InvariantDivisor invariant_divisor(int64_t d) {
  const uint64_t u = static_cast<uint64_t>(d);
  return {u, UINT64_MAX / u};
}

// fx::div_round(n, d): the quotient ties toward +inf. Branch-free: the
// corrections and the sign are selects, not jumps (the numerators' signs and
// remainders vary from call to call, so branches on them mispredict).
inline int64_t div_round_by(int64_t n, const InvariantDivisor& v) {
  const uint64_t a = fx::magnitude(n);
  // m > (2^64 - 1) / d - 1, so a m / 2^64 > a / d - 2: the estimate is
  // floor(a / d) less 0, 1 or 2, never more.
  uint64_t q = fx::mul_u64(a, v.m).hi;
  uint64_t r = a - q * v.d;
  for (int i = 0; i < 2; ++i) {
    const uint64_t over = static_cast<uint64_t>(r >= v.d);
    q += over;
    r -= v.d & (uint64_t{0} - over);
  }
  // q, r: magnitudes of the truncated quotient and of the remainder; r < d
  // <= 2^63, so 2 r + 1 fits. The magnitude rounds up at 2 r >= d for n >= 0
  // and at 2 r > d for n < 0 (either implies r != 0).
  const uint64_t negative = static_cast<uint64_t>(n < 0);
  const uint64_t up = static_cast<uint64_t>(2 * r + (negative ^ 1) > v.d);
  const uint64_t sign = uint64_t{0} - negative;
  return static_cast<int64_t>(((q + up) ^ sign) - sign);  // modular: INT64_MIN / 1
}

}  // namespace sinew::elastic_skin
