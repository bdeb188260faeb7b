// Exact int64-lane helpers shared by the metaballs layer's AVX2 kernels of
// the joint regions (joint_frame_avx2.cpp, joint_blend_avx2.cpp), compiled
// for AVX2 in their own region (isa_region.hpp); call them only from AVX2
// code. Values are held sign-extended in 64-bit lanes, flags as all-ones
// lanes; mul reads the low 32 bits of each lane (vpmuldq), the scalar
// 32x32->64 product of two int32 values.
#pragma once

#include <immintrin.h>

#include <cstdint>

#include "sim_core/fixed/avx2_lanes.hpp"
#include "sim_core/fixed/isa_region.hpp"
#include "sim_core/fixed/q_formats.hpp"
#include "sim_core/fixed/vec3.hpp"

SINEW_ISA_BEGIN("avx2")

namespace sinew::metaballs::detail::joint_lanes {
// Internal linkage: no copy of a helper outlives its own file's AVX2 code.
namespace {

using fx::avx2::round_shift_epi64;
using fx::avx2::sat_i32_epi64;

constexpr uint32_t kLanes = 4;

inline __m256i mul(__m256i a, __m256i b) { return _mm256_mul_epi32(a, b); }
inline __m256i add(__m256i a, __m256i b) { return _mm256_add_epi64(a, b); }
inline __m256i sub(__m256i a, __m256i b) { return _mm256_sub_epi64(a, b); }
inline __m256i twice(__m256i a) { return _mm256_add_epi64(a, a); }
inline __m256i lanes_of(int64_t a, int64_t b, int64_t c, int64_t d) { return _mm256_setr_epi64x(a, b, c, d); }
// sat_i32(round_shift(x, 30)): the specification's q30.
inline __m256i q30(__m256i x) { return sat_i32_epi64(round_shift_epi64<fx::kUnitFracBits>(x)); }

// All ones in the lanes that are negative / outside [lo, hi] / outside int32.
inline __m256i negative_lanes(__m256i x) { return _mm256_cmpgt_epi64(_mm256_setzero_si256(), x); }
inline __m256i outside(__m256i x, int64_t lo, int64_t hi) {
  return _mm256_or_si256(_mm256_cmpgt_epi64(x, _mm256_set1_epi64x(hi)), _mm256_cmpgt_epi64(_mm256_set1_epi64x(lo), x));
}
inline __m256i outside_i32(__m256i x) { return outside(x, INT32_MIN, INT32_MAX); }

// Component a (0 x, 1 y, 2 z) of four vectors, one per lane.
inline __m256i vec_lanes(const fx::Vec3* const p[kLanes], int a) {
  const auto at = [a](const fx::Vec3* v) { return int64_t{a == 0 ? v->x : (a == 1 ? v->y : v->z)}; };
  return lanes_of(at(p[0]), at(p[1]), at(p[2]), at(p[3]));
}

}  // namespace
}  // namespace sinew::metaballs::detail::joint_lanes

SINEW_ISA_END
