// AVX2 forward and backward sweeps of ldlt_solve_axes for a factor with
// every |L_ij| <= 1 (ldlt_skyline.cpp proves it per factor), with the
// scalar specification's words, saturation count included. Compiled for
// AVX2 (isa_region.hpp), on x86-64 only; called only when the CPU reports
// AVX2.
//   - A node's x, y and z in three int64 lanes (the fourth is zero and stays
//     zero), loaded and stored as 16 + 8 bytes, the widths the sweeps write,
//     so every reload forwards from the stores before it.
//   - The product round_half_up(l v / 2^30) of a Q2.30 entry l and a solve
//     value v (|v| <= 2^61) from two vpmuldq of int32 halves: with v =
//     vh 2^31 + vl (vh = v >> 31, |vh| <= 2^30; vl = v mod 2^31 >= 0),
//     floor((l v + 2^29) / 2^30) = 2 l vh + floor((l vl + 2^29) / 2^30),
//     since 2^31 is a multiple of 2^30; |l vl| < 2^61, so adding 2^62 makes
//     the second term's numerator non-negative and a logical shift floors
//     it (AVX2 has no 64-bit arithmetic shift).
//   - The forward sums are plain adds with each step's signed overflow
//     flagged; a row that flags one is summed again by the specification
//     (its inputs are earlier rows, unchanged), so saturating sums keep
//     their words. A value leaving +-2^61 (flagged by a window test that
//     also catches +2^61 itself, harmlessly) is clamped and counted in
//     scalar code, as the specification does.
#include <immintrin.h>

#include "ldlt_skyline.hpp"
#include "sim_core/fixed/isa_region.hpp"
#include "wide_sat.hpp"

SINEW_ISA_BEGIN("avx2")

namespace sinew::barnet::detail {
namespace {

inline __m256i load_node(const int64_t* p) {
  const __m128i xy = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
  const __m128i z = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p + 2));
  return _mm256_inserti128_si256(_mm256_castsi128_si256(xy), z, 1);
}

inline void store_node(int64_t* p, __m256i v) {
  _mm_storeu_si128(reinterpret_cast<__m128i*>(p), _mm256_castsi256_si128(v));
  _mm_storel_epi64(reinterpret_cast<__m128i*>(p + 2), _mm256_extracti128_si256(v, 1));
}

// v split for vpmuldq: the low 32 bits of each lane hold vh = v >> 31 (bits
// 31..62 of v: its sign for |v| <= 2^61) and vl = v mod 2^31.
struct Split {
  __m256i high, low;
};
inline Split split(__m256i v) {
  return {_mm256_srli_epi64(v, 31), _mm256_and_si256(v, _mm256_set1_epi64x((int64_t{1} << 31) - 1))};
}

// round_half_up(l v / 2^30) per lane (mul_l30_unit_bounded's value).
inline __m256i product(__m256i l, Split v) {
  const __m256i bias = _mm256_set1_epi64x((int64_t{1} << 62) + (int64_t{1} << 29));
  const __m256i high = _mm256_mul_epi32(l, v.high);
  const __m256i low = _mm256_srli_epi64(_mm256_add_epi64(_mm256_mul_epi32(l, v.low), bias), 30);
  return _mm256_sub_epi64(_mm256_add_epi64(_mm256_add_epi64(high, high), low), _mm256_set1_epi64x(int64_t{1} << 32));
}

// True if some lane may lie outside [-2^61, 2^61] (also for +2^61 itself).
inline bool maybe_beyond_limit(__m256i v) {
  const __m256i shifted = _mm256_srli_epi64(_mm256_add_epi64(v, _mm256_set1_epi64x(kVectorLimit)), 62);
  return _mm256_testz_si256(shifted, shifted) == 0;
}

// The specification's clamp of a node's three values, counting.
inline void store_clamped(int64_t* p, __m256i v, fx::Saturation& sat) {
  alignas(32) int64_t w[4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(w), v);
  for (int c = 0; c < 3; ++c) p[c] = clamp_vector(w[c], sat);
}

}  // namespace

void solve_forward_unit_avx2(const SkylineFactor& f, int64_t* x, fx::Saturation& sat) {
  for (uint32_t i = 0; i < f.n; ++i) {
    const uint32_t fi = f.first[i];
    const int32_t* li = f.lower.data() + f.offset[i];
    __m256i y = load_node(x + 3 * i);
    __m256i overflow = _mm256_setzero_si256();
    for (uint32_t j = fi; j < i; ++j) {
      const __m256i p = product(_mm256_set1_epi32(li[j - fi]), split(load_node(x + 3 * j)));
      const __m256i r = _mm256_sub_epi64(y, p);
      // y - p overflows iff y and p differ in sign and r differs from y.
      overflow = _mm256_or_si256(overflow, _mm256_and_si256(_mm256_xor_si256(y, p), _mm256_xor_si256(y, r)));
      y = r;
    }
    if (_mm256_movemask_pd(_mm256_castsi256_pd(overflow)) != 0) {
      // A saturating sum: the specification's, word for word.
      int64_t s[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
      for (uint32_t j = fi; j < i; ++j)
        for (uint32_t c = 0; c < 3; ++c) s[c] = fx::add_sat_i64(s[c], -mul_l30_unit_bounded(li[j - fi], x[3 * j + c]));
      for (uint32_t c = 0; c < 3; ++c) x[3 * i + c] = clamp_vector(s[c], sat);
    } else if (maybe_beyond_limit(y)) {
      store_clamped(x + 3 * i, y, sat);
    } else {
      store_node(x + 3 * i, y);
    }
  }
}

void solve_backward_unit_avx2(const SkylineFactor& f, int64_t* x, fx::Saturation& sat) {
  for (uint32_t i = f.n; i-- > 0;) {
    const uint32_t fi = f.first[i];
    const int32_t* li = f.lower.data() + f.offset[i];
    const Split xi = split(load_node(x + 3 * i));
    for (uint32_t j = fi; j < i; ++j) {
      // |x_j| <= 2^61 and |p| <= 2^61 + 1: the difference is exact.
      const __m256i r = _mm256_sub_epi64(load_node(x + 3 * j), product(_mm256_set1_epi32(li[j - fi]), xi));
      if (maybe_beyond_limit(r)) {
        store_clamped(x + 3 * j, r, sat);
      } else {
        store_node(x + 3 * j, r);
      }
    }
  }
}

}  // namespace sinew::barnet::detail

SINEW_ISA_END
