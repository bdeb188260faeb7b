// Shared normalisation kernel: divides components by the Euclidean norm of a
// (possibly different) set of components, with one rounding per output.
#pragma once

#include <cstdint>

#include "q_formats.hpp"

namespace sinew::fx {

// Reciprocal-norm divisor of up to 4 int32 components. The components are
// first scaled by 2^shift so the largest lies in [2^29, 2^30) (right shifts
// round; they only happen for components >= 1.0 in Q2.30), and the norm of
// the scaled values is taken with a correctly rounded integer sqrt.
struct NormDivisor {
  int64_t length;  // round(2 * |scaled components|), >= 2^30; 0 for a zero vector
  int shift;       // scale exponent applied before the norm, in [-2, 30]
};

NormDivisor norm_divisor(const int32_t* components, int count);

// value / |components| in Q2.30 for value in the components' own format
// (value may be another vector sharing that norm, e.g. a dual part).
int32_t divide_by_norm(int32_t value, const NormDivisor& d);

}  // namespace sinew::fx
