// Base-2 logarithm, exponential and power in integer fixed point (the
// general superquadric exponents of the muscle primitives, LEMAN §5.2,
// [Barr 81]). Pure integer, identical bits on every platform.
//
// Formats: a logarithm or exponent argument is Q30 in an int64 (value
// x / 2^30); an exponential's result is round(2^x * 2^frac_bits) in an int64,
// frac_bits chosen by the caller (0..62). Powers p are Q16.16.
//
// Method (both kernels work in unsigned Q62, far below the Q30 step):
//   log2: v = 2^k m, m in [1, 2); m (1 + i/32)^-1 = 1 + t, 0 <= t < 2^-5
//         (32-entry tables of 1/(1 + i/32) and log2(1 + i/32));
//         log2(1 + t) by Horner over 8 terms of log2(e) t^n / n.
//   exp2: x = n + j/32 + s, 0 <= s < 2^-5; 2^(j/32) from a 32-entry table
//         times 2^s by Horner over 6 terms of (s ln 2)^n / n!; shifted by
//         n + frac_bits - 62.
// Products are 64x64 -> 128 bits (wide.hpp), truncated to Q62 inside the
// kernels, rounded half up once at the end. Each kernel is within 2^-46 of
// its exact value (series remainder and roundings): log2_q30 returns the
// correctly rounded value to within 0.5 LSB plus 2^-16 LSB (ties may go
// either way), exp2_fixed to within 0.5 LSB plus 2^-46 of the result.
// Measured and enforced in tests/sim_core/fixed/fixed_log_exp_test.cpp and tabled in
// docs/numerics.md.
#pragma once

#include <cstdint>

namespace sinew::fx {

// log2(0), as returned by log2_q30: -2^20 in Q30. 2^(that) is 0 in every
// format, and products with a Q16.16 power (|p| < 2^31) stay inside int64.
inline constexpr int64_t kLog2OfZero = -(int64_t{1} << 50);

// log2(v / 2^frac_bits) in Q30, rounded half up; 0 <= frac_bits <= 63.
// v = 0 gives kLog2OfZero. Range: [-63, 64) for v >= 1.
int64_t log2_q30(uint64_t v, int frac_bits);

// round(2^(x / 2^30) * 2^frac_bits), 0 <= frac_bits <= 62. Saturates at
// INT64_MAX (x / 2^30 + frac_bits >= 63), 0 below half an LSB.
int64_t exp2_fixed(int64_t x_q30, int frac_bits);

// (v / 2^v_frac)^(p / 2^16) as exp2_fixed(p log2 v, out_frac): the product
// p log2 v is rounded once to Q30, so the exponent is off by at most
// (|p| + 1) 2^-31 (|p| half LSBs of the logarithm and the product's own
// rounding) and the result's relative error is at most (|p| + 1) 2^-31 ln 2
// plus its half LSB (|p| <= 16: 8.2e-9). v = 0 gives 0 for p > 0, 1 for
// p = 0 and INT64_MAX for p < 0.
int64_t pow_fixed(uint64_t v, int v_frac, int32_t p_q16, int out_frac);

// The tables the kernels use (Q62), for their unit test: 1/(1 + i/32),
// log2(1 + i/32) and 2^(i/32), i = 0..31.
inline constexpr int kLogExpTableSize = 32;
extern const int64_t kReciprocalTableQ62[kLogExpTableSize];
extern const int64_t kLog2TableQ62[kLogExpTableSize];
extern const int64_t kExp2TableQ62[kLogExpTableSize];

}  // namespace sinew::fx
