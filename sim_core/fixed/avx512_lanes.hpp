// Exact int64-lane helpers shared by the AVX-512 kernels (F + VL + CD),
// compiled for them in their own region (isa_region.hpp); call them only from
// code that checked the CPU for all three. Every helper gives, lane by lane,
// the words of the scalar operation it names in sim_core/fixed (wrapping
// vector adds: no UB, same bits).
#pragma once

#include <immintrin.h>

#include <cstdint>

#include "sim_core/fixed/isa_region.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"

SINEW_ISA_BEGIN("avx512f,avx512vl,avx512cd")

namespace sinew::fx::avx512 {
// Internal linkage: no copy of a helper outlives its own file's AVX-512 code.
namespace {

// round_shift(x, S) of scalar.hpp on every int64 lane: (x >> S) + bit S-1 of
// x, which is floor((x + 2^(S-1)) / 2^S) with no offset and no overflow.
template <int S>
inline __m512i round_shift_epi64(__m512i x) {
  return _mm512_add_epi64(_mm512_srai_epi64(x, S), _mm512_and_si512(_mm512_srli_epi64(x, S - 1), _mm512_set1_epi64(1)));
}

// sat_i32 of every int64 lane (the result still in int64 lanes).
inline __m512i sat_i32_epi64(__m512i x) {
  return _mm512_min_epi64(_mm512_max_epi64(x, _mm512_set1_epi64(INT32_MIN)), _mm512_set1_epi64(INT32_MAX));
}

// fx::rsqrt_fast on 8 nonzero unsigned lanes: y (Q30, below 2^31) and the
// right shift 31 - half_shift (in [0, 31]) that scales c * y to c / sqrt(n2)
// in Q30. countl_zero is vplzcntq; the seed table is read by a gather; the
// Newton steps run on non-negative values below 2^32 (unsigned 32x32
// products, each below 2^63), as in the scalar function.
struct RsqrtX8 {
  __m512i y;
  __m512i shift;
};

inline RsqrtX8 rsqrt_fast_x8(__m512i n2) {
  const __m512i s = _mm512_andnot_si512(_mm512_set1_epi64(1), _mm512_lzcnt_epi64(n2));  // even
  const __m512i m = _mm512_sllv_epi64(n2, s);                                           // [2^62, 2^64)
  const __m512i index = _mm512_sub_epi64(_mm512_srli_epi64(m, 56), _mm512_set1_epi64(64));
  static_assert(sizeof(fx::detail::kRsqrtSeed[0]) == sizeof(int));
  __m512i r = _mm512_cvtepu32_epi64(
      _mm512_i64gather_epi32(index, reinterpret_cast<const int*>(fx::detail::kRsqrtSeed.data()), 4));
  const __m512i v = _mm512_srli_epi64(m, 32);  // Q30, [2^30, 2^32)
  const __m512i three = _mm512_set1_epi64(int64_t{3} << 30);
  for (int i = 0; i < 2; ++i) {
    const __m512i r2 = _mm512_srli_epi64(_mm512_mul_epu32(r, r), 30);
    const __m512i vr2 = _mm512_srli_epi64(_mm512_mul_epu32(v, r2), 30);
    r = _mm512_srli_epi64(_mm512_mul_epu32(r, _mm512_sub_epi64(three, vr2)), 31);
  }
  return {r, _mm512_sub_epi64(_mm512_set1_epi64(31), _mm512_srli_epi64(s, 1))};
}

// fx::normalize_fast on 8 vectors at once (same words, zero vectors to
// zero): c * y rounded right by 31 - half_shift per lane, then sat_i32. The
// per-lane round_shift is (p + 2^(s-1)) >> s, s = 0 adding nothing: |c y| <
// 2^62, so the sum cannot overflow.
inline void normalize_fast_x8(__m512i x, __m512i y, __m512i z, __m512i out[3]) {
  const __m512i n2 =
      _mm512_add_epi64(_mm512_add_epi64(_mm512_mul_epi32(x, x), _mm512_mul_epi32(y, y)), _mm512_mul_epi32(z, z));
  const __mmask8 nonzero = _mm512_test_epi64_mask(n2, n2);
  const RsqrtX8 r = rsqrt_fast_x8(_mm512_mask_blend_epi64(nonzero, _mm512_set1_epi64(1), n2));
  const __m512i bias = _mm512_srli_epi64(_mm512_sllv_epi64(_mm512_set1_epi64(1), r.shift), 1);
  const __m512i c[3] = {x, y, z};
  for (int i = 0; i < 3; ++i) {
    const __m512i p = _mm512_srav_epi64(_mm512_add_epi64(_mm512_mul_epi32(c[i], r.y), bias), r.shift);
    out[i] = _mm512_maskz_mov_epi64(nonzero, sat_i32_epi64(p));
  }
}

}  // namespace
}  // namespace sinew::fx::avx512

SINEW_ISA_END
