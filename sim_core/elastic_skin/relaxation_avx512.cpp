// AVX-512 (F + VL + CD) kernels of two relaxation passes (relaxation.cpp),
// the same words as the scalar specification for every input.
//
// The edge pass (pull_of): eight edges per step, one per 64-bit lane:
//   - the edges' ends, rest lengths and stiffnesses are read by permutes
//     when the eight are consecutive edges, else by gathers; the ends'
//     positions by gathers;
//   - w = sub_sat(x_b, x_a) and |w|^2 exactly (each square < 2^62, the sum
//     below 2^64 as the scalar uint64 sum);
//   - 1 / |w| by fx::avx512::rsqrt_fast_x8 (fx::rsqrt_fast's words), rest /
//     |w| as edge_spring rounds it, and ratio = 1 - rest / |w|;
//   - a lane with ratio < 0 (a compressed edge: its stiffness needs the exact
//     root and the push-back band) is finished by the specification's
//     compressed branch (pull_compressed_edge) from the lane's w, |w|^2 and
//     ratio, which overwrites what the group stored for it;
//   - the pulls round_shift(w ratio, 30) (within int32 without a clamp), stored
//     contiguously when the eight edges are consecutive, else one by one.
//
// The collision pass (collide_with_anchor_spheres): eight vertices per
// step; d = sub_sat(x, centre), |d|^2 as an unsigned sum (the saturating
// scalar sum compares with r^2 < 2^62 the same way), the direction by
// fx::avx512::normalize_fast_x8 (fx::normalize_fast's words), and
// centre + mul_by_unit(R, dir) with add_sat, stored under the inside lanes'
// mask; a vertex at its sphere's centre (d = 0) is left to the
// specification, which puts it at its anchor.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
// GCC 12's AVX-512 headers (GCC bug 105593, fixed in GCC 13).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <immintrin.h>

#include <cstring>

#include "relaxation_kernels.hpp"
#include "sim_core/fixed/avx512_lanes.hpp"
#include "sim_core/fixed/isa_region.hpp"

SINEW_ISA_BEGIN("avx512f,avx512vl,avx512cd")

namespace sinew::elastic_skin::detail {
namespace {

using fx::avx512::round_shift_epi64;
using fx::avx512::sat_i32_epi64;

static_assert(sizeof(Edge) == 4 * sizeof(int32_t));

// Field f (0 a, 1 b, 2 rest, 3 k) of eight edges, sign-extended to 64-bit lanes.
struct EdgeLanes {
  __m512i field[4];
};

inline EdgeLanes consecutive_edges(const Edge* first) {
  const int32_t* words = reinterpret_cast<const int32_t*>(first);
  const __m512i lo = _mm512_loadu_si512(words), hi = _mm512_loadu_si512(words + 16);
  EdgeLanes e;
  for (int f = 0; f < 4; ++f) {
    const __m512i pick =
        _mm512_add_epi32(_mm512_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28, 0, 0, 0, 0, 0, 0, 0, 0), _mm512_set1_epi32(f));
    e.field[f] = _mm512_cvtepi32_epi64(_mm512_castsi512_si256(_mm512_permutex2var_epi32(lo, pick, hi)));
  }
  return e;
}

inline EdgeLanes gathered_edges(const Edge* edges, __m256i index) {
  const int* words = reinterpret_cast<const int*>(edges);
  const __m256i at = _mm256_slli_epi32(index, 2);
  EdgeLanes e;
  for (int f = 0; f < 4; ++f) e.field[f] = _mm512_cvtepi32_epi64(_mm256_i32gather_epi32(words + f, at, 4));
  return e;
}

// Stores eight int32 lanes at column[e] for the group's edges.
inline void store(int32_t* column, __m512i lanes, const uint32_t* edge, bool consecutive) {
  const __m256i words = _mm512_cvtepi64_epi32(lanes);
  if (consecutive) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(column + edge[0]), words);
    return;
  }
  int32_t w[8];
  std::memcpy(w, &words, sizeof(w));
  for (int l = 0; l < 8; ++l) column[edge[l]] = w[l];
}

}  // namespace

uint32_t pull_edges_avx512(const EdgePullJob& job, uint32_t begin, uint32_t end) {
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m512i zero = _mm512_setzero_si512();
  const __m512i one = _mm512_set1_epi64(1);
  const __m512i unit = _mm512_set1_epi64(fx::kUnitOne);
  uint32_t i = begin;
  for (; end - i >= 8; i += 8) {
    const uint32_t* edge = job.moving + i;
    const __m256i index = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(edge));
    const bool consecutive =
        _mm256_cmpeq_epi32_mask(index, _mm256_add_epi32(_mm256_set1_epi32(static_cast<int32_t>(edge[0])), lane)) ==
        0xFF;
    const EdgeLanes e = consecutive ? consecutive_edges(job.edges + edge[0]) : gathered_edges(job.edges, index);
    const __m256i a = _mm512_cvtepi64_epi32(e.field[0]), b = _mm512_cvtepi64_epi32(e.field[1]);
    __m512i w[3];
    __m512i n2 = zero;
    for (int c = 0; c < 3; ++c) {
      const int* column = reinterpret_cast<const int*>(job.position[c]);
      const __m512i xa = _mm512_cvtepi32_epi64(_mm256_i32gather_epi32(column, a, 4));
      const __m512i xb = _mm512_cvtepi32_epi64(_mm256_i32gather_epi32(column, b, 4));
      w[c] = sat_i32_epi64(_mm512_sub_epi64(xb, xa));  // fx::sub: sub_sat per component
      n2 = _mm512_add_epi64(n2, _mm512_mul_epi32(w[c], w[c]));
    }
    // Lanes that pull with nothing (pull_of's early returns): n2 == 0 or k == 0.
    const __mmask8 pulls =
        static_cast<__mmask8>(_mm512_test_epi64_mask(n2, n2) & _mm512_test_epi64_mask(e.field[3], e.field[3]));
    const fx::avx512::RsqrtX8 r = fx::avx512::rsqrt_fast_x8(_mm512_mask_blend_epi64(pulls, one, n2));
    // edge_spring: rest y rounded right by 31 - half_shift (none at 0);
    // |rest y| < 2^62, so adding the bias cannot overflow.
    const __m512i bias = _mm512_srli_epi64(_mm512_sllv_epi64(one, r.shift), 1);
    const __m512i rest_over_len = _mm512_srav_epi64(_mm512_add_epi64(_mm512_mul_epi32(e.field[2], r.y), bias), r.shift);
    const __m512i ratio = _mm512_sub_epi64(unit, rest_over_len);
    const __mmask8 compressed = static_cast<__mmask8>(pulls & _mm512_cmplt_epi64_mask(ratio, zero));
    // Not compressed: 0 <= ratio <= 2^30, a vpmuldq operand, and k is
    // Edge::k. |w_c| <= 2^31 then keeps |w_c ratio| / 2^30 within int32 (only
    // -2^31 reaches 2^31): pull_of's sat_i32 is the identity here.
    store(job.stiffness, _mm512_maskz_mov_epi64(pulls, e.field[3]), edge, consecutive);
    for (int c = 0; c < 3; ++c) {
      const __m512i f = round_shift_epi64<fx::kUnitFracBits>(_mm512_mul_epi32(w[c], ratio));
      store(job.pull[c], _mm512_maskz_mov_epi64(pulls, f), edge, consecutive);
    }
    if (compressed != 0) {
      int64_t wl[3][8], ratio_l[8], n2_l[8];
      for (int c = 0; c < 3; ++c) _mm512_storeu_si512(wl[c], w[c]);
      _mm512_storeu_si512(ratio_l, ratio);
      _mm512_storeu_si512(n2_l, n2);
      for (uint32_t bad = compressed; bad != 0; bad &= bad - 1) {
        const int l = __builtin_ctz(bad);
        const int64_t wc[3] = {wl[0][l], wl[1][l], wl[2][l]};
        pull_compressed_edge(job, edge[l], wc, ratio_l[l], static_cast<uint64_t>(n2_l[l]));
      }
    }
  }
  return i;
}

namespace {

inline __m512i lanes_of(const int32_t* column, __m256i index, const uint32_t* at, bool consecutive) {
  if (consecutive) return _mm512_cvtepi32_epi64(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(column + at[0])));
  return _mm512_cvtepi32_epi64(_mm256_i32gather_epi32(column, index, 4));
}

}  // namespace

uint32_t collide_with_spheres_avx512(const SphereJob& job, uint32_t begin, uint32_t end, uint32_t* moved) {
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const int64_t r = int64_t{job.radius} - 2;  // 2 LSB of slack, as the specification
  const __m512i r2 = _mm512_set1_epi64(r * r);
  const __m512i radius = _mm512_set1_epi64(job.radius);
  uint32_t i = begin;
  for (; end - i >= 8; i += 8) {
    const uint32_t* at = job.moving + i;
    const __m256i index = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(at));
    const bool consecutive =
        _mm256_cmpeq_epi32_mask(index, _mm256_add_epi32(_mm256_set1_epi32(static_cast<int32_t>(at[0])), lane)) == 0xFF;
    __m512i centre[3], d[3];
    __m512i n2 = _mm512_setzero_si512();
    for (int c = 0; c < 3; ++c) {
      centre[c] = lanes_of(job.centre[c], index, at, consecutive);
      d[c] = sat_i32_epi64(_mm512_sub_epi64(lanes_of(job.position[c], index, at, consecutive), centre[c]));
      n2 = _mm512_add_epi64(n2, _mm512_mul_epi32(d[c], d[c]));  // each < 2^62 + 1, the sum < 2^64
    }
    const __mmask8 inside = _mm512_cmplt_epu64_mask(n2, r2);
    if (inside == 0) continue;
    const __mmask8 at_centre = static_cast<__mmask8>(inside & _mm512_testn_epi64_mask(n2, n2));
    const __mmask8 out = static_cast<__mmask8>(inside & ~at_centre);
    __m512i dir[3];
    fx::avx512::normalize_fast_x8(d[0], d[1], d[2], dir);
    for (int c = 0; c < 3; ++c) {
      // mul_by_unit(R, dir_c), then add_sat: both within int64 before the clamps.
      const __m512i offset = sat_i32_epi64(round_shift_epi64<fx::kUnitFracBits>(_mm512_mul_epi32(radius, dir[c])));
      const __m256i word = _mm512_cvtepi64_epi32(sat_i32_epi64(_mm512_add_epi64(centre[c], offset)));
      if (consecutive) {
        _mm256_mask_storeu_epi32(job.position[c] + at[0], out, word);
      } else {
        int32_t w[8];
        std::memcpy(w, &word, sizeof(w));
        for (uint32_t m = out; m != 0; m &= m - 1) {
          const int l = __builtin_ctz(m);
          job.position[c][at[l]] = w[l];
        }
      }
    }
    *moved += static_cast<uint32_t>(__builtin_popcount(out));
    for (uint32_t m = at_centre; m != 0; m &= m - 1)
      *moved += collide_vertex_scalar(job, i + static_cast<uint32_t>(__builtin_ctz(m)));
  }
  return i;
}

}  // namespace sinew::elastic_skin::detail

SINEW_ISA_END
