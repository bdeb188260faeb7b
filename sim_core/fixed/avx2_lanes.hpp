// Exact int64-lane helpers shared by the AVX2 kernels, compiled for AVX2 in
// their own region (isa_region.hpp); call them only from AVX2 code.
// Every helper gives, lane by lane, the words of the scalar operation it
// names in sim_core/fixed (wrapping vector adds: no UB, same bits).
#pragma once

#include <immintrin.h>

#include <cstdint>
#include <cstring>

#include "sim_core/fixed/isa_region.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"

SINEW_ISA_BEGIN("avx2")

namespace sinew::fx::avx2 {
// Internal linkage: no copy of a helper outlives its own file's AVX2 code.
namespace {

// round_shift(x, s) of scalar.hpp on every int64 lane: ((x + 2^(s-1) + 2^63)
// >>> s) - 2^(63-s). AVX2 has no 64-bit arithmetic right shift: the 2^63
// offset maps int64 order-preserving onto uint64, exact for every int64.
template <int S>
inline __m256i round_shift_epi64(__m256i x) {
  const __m256i bias = _mm256_set1_epi64x(INT64_MIN + (int64_t{1} << (S - 1)));
  const __m256i offset = _mm256_set1_epi64x(int64_t{1} << (63 - S));
  return _mm256_sub_epi64(_mm256_srli_epi64(_mm256_add_epi64(x, bias), S), offset);
}

// True if every lane lies in [lo, lo + 2^bits).
template <int Bits>
inline bool all_in_window(__m256i x, int64_t lo) {
  const __m256i above = _mm256_srli_epi64(_mm256_sub_epi64(x, _mm256_set1_epi64x(lo)), Bits);
  return _mm256_testz_si256(above, above) != 0;
}

// sat_i32 of every int64 lane (the result still in int64 lanes).
inline __m256i sat_i32_epi64(__m256i x) {
  if (all_in_window<32>(x, INT32_MIN)) return x;
  const __m256i hi = _mm256_set1_epi64x(INT32_MAX);
  const __m256i lo = _mm256_set1_epi64x(INT32_MIN);
  x = _mm256_blendv_epi8(x, hi, _mm256_cmpgt_epi64(x, hi));
  return _mm256_blendv_epi8(x, lo, _mm256_cmpgt_epi64(lo, x));
}

inline void lanes(__m256i x, int64_t out[4]) { std::memcpy(out, &x, sizeof(x)); }

inline __m256i load4_epi64(const int32_t* p) {
  __m128i x;
  std::memcpy(&x, p, sizeof(x));
  return _mm256_cvtepi32_epi64(x);
}

// count_leading_zeros(x) & ~1 and x shifted left by it, per lane, for x != 0:
// binary search over even shifts with unsigned tests (x < 2^k iff x >> k == 0).
inline __m256i even_normalise_shift(__m256i* x) {
  __m256i shift = _mm256_setzero_si256();
  const auto step = [&](int below, int64_t by) {
    const __m256i small = _mm256_cmpeq_epi64(_mm256_srli_epi64(*x, below), _mm256_setzero_si256());
    const __m256i s = _mm256_and_si256(small, _mm256_set1_epi64x(by));
    *x = _mm256_sllv_epi64(*x, s);
    shift = _mm256_add_epi64(shift, s);
  };
  step(32, 32);
  step(48, 16);
  step(56, 8);
  step(60, 4);
  step(62, 2);
  return shift;
}

// fx::rsqrt_fast on 4 nonzero unsigned lanes: y (Q30, below 2^31) and the
// right shift 31 - half_shift (in [0, 31]) that scales c * y to c / sqrt(n2)
// in Q30. The seed table is read by a gather, the Newton steps run on
// non-negative values below 2^32 (unsigned 32x32 products).
struct RsqrtX4 {
  __m256i y;
  __m256i shift;
};

inline RsqrtX4 rsqrt_fast_x4(__m256i n2) {
  const __m256i s = even_normalise_shift(&n2);  // n2 is now m in [2^62, 2^64)
  const __m256i index = _mm256_sub_epi64(_mm256_srli_epi64(n2, 56), _mm256_set1_epi64x(64));
  static_assert(sizeof(fx::detail::kRsqrtSeed[0]) == sizeof(int));
  __m256i r = _mm256_cvtepu32_epi64(
      _mm256_i64gather_epi32(reinterpret_cast<const int*>(fx::detail::kRsqrtSeed.data()), index, 4));
  const __m256i v = _mm256_srli_epi64(n2, 32);  // Q30, [2^30, 2^32)
  const __m256i three = _mm256_set1_epi64x(int64_t{3} << 30);
  for (int i = 0; i < 2; ++i) {
    // r < 2^31, r2 <= ~2^30, v r2 / 2^30 within 1% of 2^30: every operand is
    // non-negative and below 2^32, every product below 2^63.
    const __m256i r2 = _mm256_srli_epi64(_mm256_mul_epu32(r, r), 30);
    const __m256i vr2 = _mm256_srli_epi64(_mm256_mul_epu32(v, r2), 30);
    r = _mm256_srli_epi64(_mm256_mul_epu32(r, _mm256_sub_epi64(three, vr2)), 31);
  }
  return {r, _mm256_sub_epi64(_mm256_set1_epi64x(31), _mm256_srli_epi64(s, 1))};
}

// round_shift by a per-lane shift in [0, 31], 0 meaning none (as the scalar
// `shift > 0 ? round_shift(p, shift) : p`), for every int64 lane.
struct VarRoundShift {
  __m256i shift, bias, offset;
  explicit VarRoundShift(__m256i s)
      : shift(s),
        bias(_mm256_add_epi64(_mm256_srli_epi64(_mm256_sllv_epi64(_mm256_set1_epi64x(1), s), 1),
                              _mm256_set1_epi64x(INT64_MIN))),
        offset(_mm256_srlv_epi64(_mm256_set1_epi64x(INT64_MIN), s)) {}  // 2^(63 - shift)
  __m256i operator()(__m256i p) const {
    return _mm256_sub_epi64(_mm256_srlv_epi64(_mm256_add_epi64(p, bias), shift), offset);
  }
};

// fx::normalize_fast on 4 vectors at once (same words): rsqrt_fast's seed and
// Newton steps on non-negative values below 2^32 (unsigned 32x32 products),
// then round_shift by 31 - half_shift per lane and sat_i32.
inline void normalize_fast_x4(__m256i x, __m256i y, __m256i z, __m256i out[3]) {
  const __m256i zero = _mm256_setzero_si256();
  // Sum of squares: each < 2^62 + 1, the sum < 2^64 (unsigned, wrapping adds exact).
  __m256i n2 =
      _mm256_add_epi64(_mm256_add_epi64(_mm256_mul_epi32(x, x), _mm256_mul_epi32(y, y)), _mm256_mul_epi32(z, z));
  const __m256i is_zero = _mm256_cmpeq_epi64(n2, zero);
  n2 = _mm256_blendv_epi8(n2, _mm256_set1_epi64x(1), is_zero);  // any valid lane; zeroed below
  const RsqrtX4 r = rsqrt_fast_x4(n2);
  const VarRoundShift scale(r.shift);
  const __m256i c[3] = {x, y, z};
  for (int i = 0; i < 3; ++i) out[i] = _mm256_andnot_si256(is_zero, sat_i32_epi64(scale(_mm256_mul_epi32(c[i], r.y))));
}

}  // namespace
}  // namespace sinew::fx::avx2

SINEW_ISA_END
