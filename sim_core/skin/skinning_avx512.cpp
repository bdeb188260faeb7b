// AVX-512 (F + VL) kernel of linear blend skinning: the same output words and
// the same saturation count as the scalar specification (skinning.cpp) for
// every input. Its functions are compiled for AVX-512 F + VL
// (isa_region.hpp), on x86-64 only; called only when the CPU reports both
// (skinning.cpp).
//
// The layout of the AVX2 kernel (one vertex per step, one 64-bit lane per row
// of the blended transform, the palette widened once per call), with the
// instructions AVX2 lacks:
//   - round half up is (x >> s) + ((x >> (s-1)) & 1) with the 64-bit
//     arithmetic shift vpsraq: floor((x + 2^(s-1)) / 2^s) for every int64,
//     with no offset and no overflow;
//   - the linear part's range check is two mask compares (vpcmpq) against
//     [-2^30, 2^30], where the scalar clamp is the identity; a vertex outside
//     is redone by the specification, which counts the clamp;
//   - sat_i32 is vpmaxsq then vpminsq.
// Normals are renormalised after each block by the AVX2 kernel's four-lane
// normalize_fast (every AVX-512 CPU has AVX2). Palettes larger than the
// widened buffer and K outside 1..8 take the scalar specification; DQS
// vertices are skipped (their own kernel writes them).
#include <immintrin.h>

#include <cstring>

#include "sim_core/fixed/isa_region.hpp"
#include "skinning_detail.hpp"

SINEW_ISA_BEGIN("avx512f,avx512vl")

#include "lbs_blocks.hpp"

namespace sinew::skin::detail {
namespace {

constexpr size_t kMaxWidePalette512 = 256;  // 128 bytes per entry on the stack

struct WideEntry512 {
  __m256i col[4];  // linear columns 0..2 and the translation; lane r is row r, lane 3 zero
};

inline WideEntry512 widen512(const fx::Mat34& m) {
  return {{_mm256_setr_epi64x(m.m[0][0], m.m[1][0], m.m[2][0], 0),
           _mm256_setr_epi64x(m.m[0][1], m.m[1][1], m.m[2][1], 0),
           _mm256_setr_epi64x(m.m[0][2], m.m[1][2], m.m[2][2], 0), _mm256_setr_epi64x(m.t[0], m.t[1], m.t[2], 0)}};
}

// fx::round_shift(x, S) on every int64 lane.
template <int S>
inline __m256i round_shift_512(__m256i x) {
  const __m256i one = _mm256_set1_epi64x(1);
  return _mm256_add_epi64(_mm256_srai_epi64(x, S), _mm256_and_si256(_mm256_srli_epi64(x, S - 1), one));
}

// fx::sat_i32 on every int64 lane.
inline __m256i sat_i32_512(__m256i x) {
  return _mm256_min_epi64(_mm256_max_epi64(x, _mm256_set1_epi64x(INT32_MIN)), _mm256_set1_epi64x(INT32_MAX));
}

// Row-wise M v for the blended columns (Q8.24) and a broadcast int32 vector;
// vpmuldq reads the low half of each lane, where the entries are.
inline __m256i apply_linear_512(const __m256i col[3], int32_t v0, int32_t v1, int32_t v2) {
  __m256i acc = _mm256_mul_epi32(col[0], _mm256_set1_epi32(v0));
  acc = _mm256_add_epi64(acc, _mm256_mul_epi32(col[1], _mm256_set1_epi32(v1)));
  return _mm256_add_epi64(acc, _mm256_mul_epi32(col[2], _mm256_set1_epi32(v2)));
}

inline void flush_normals(const SkinnedVertices& out, PendingNormals* pending) {
  const int32_t* const c[3] = {pending->c[0], pending->c[1], pending->c[2]};
  renormalise_normals_avx2(c, pending->index, pending->count, out);
  pending->count = 0;
}

struct Job512 {
  const rig::Rig* rig;
  std::span<const fx::Mat34> palette;
  const WideEntry512* wide;
  const SkinnedVertices* out;
  bool skip_dual;
  bool normals;
};

// One LBS vertex; false if its blended linear part leaves [-2^30, 2^30]
// (then nothing was written and the caller runs the specification).
template <uint32_t K>
inline bool linear_vertex_512(const Job512& job, uint32_t v, uint32_t index, PendingNormals* pending) {
  const rig::Rig& rig = *job.rig;
  const uint16_t* joints = rig.influence_palette.data() + size_t{v} * K;
  const fx::Unit* weights = rig.influence_weight.data() + size_t{v} * K;
  __m256i acc[4] = {_mm256_setzero_si256(), _mm256_setzero_si256(), _mm256_setzero_si256(), _mm256_setzero_si256()};
  for (uint32_t k = 0; k < K; ++k) {
    const WideEntry512& e = job.wide[joints[k]];
    const __m256i w = _mm256_set1_epi32(weights[k]);
    for (int c = 0; c < 4; ++c) acc[c] = _mm256_add_epi64(acc[c], _mm256_mul_epi32(e.col[c], w));
  }
  // Q2.30 x Q8.24 -> Q8.24, in range or back to the specification.
  const __m256i lo = _mm256_set1_epi64x(-(int64_t{1} << 30)), hi = _mm256_set1_epi64x(int64_t{1} << 30);
  __m256i col[3];
  __mmask8 outside = 0;
  for (int c = 0; c < 3; ++c) {
    col[c] = round_shift_512<fx::kUnitFracBits>(acc[c]);
    outside |= static_cast<__mmask8>(_mm256_cmp_epi64_mask(col[c], lo, _MM_CMPINT_LT) |
                                     _mm256_cmp_epi64_mask(col[c], hi, _MM_CMPINT_NLE));
  }
  if (outside != 0) return false;
  // Translation in Q12.20 times 2^24, as the scalar t * (1 << 24).
  const __m256i t = _mm256_slli_epi64(round_shift_512<fx::kUnitFracBits>(acc[3]), 24);
  const SkinnedVertices& out = *job.out;
  int64_t r[4];
  const __m256i p =
      _mm256_add_epi64(apply_linear_512(col, rig.position[0][v], rig.position[1][v], rig.position[2][v]), t);
  const __m256i position = sat_i32_512(round_shift_512<fx::kLinFracBits>(p));
  std::memcpy(r, &position, sizeof(r));
  for (int i = 0; i < 3; ++i) out.position[i][index] = static_cast<int32_t>(r[i]);
  if (job.normals) {
    const __m256i n = apply_linear_512(col, rig.normal[0][v], rig.normal[1][v], rig.normal[2][v]);
    const __m256i normal = sat_i32_512(round_shift_512<fx::kLinFracBits>(n));
    std::memcpy(r, &normal, sizeof(r));
    const uint32_t slot = pending->count++;
    for (int c = 0; c < 3; ++c) pending->c[c][slot] = static_cast<int32_t>(r[c]);
    pending->index[slot] = index;
  }
  return true;
}

}  // namespace

uint32_t skin_linear_avx512(const rig::Rig& rig, std::span<const fx::Mat34> palette, bool skip_dual, uint32_t first,
                            uint32_t count, const SkinnedVertices& out) {
  WideEntry512 wide[kMaxWidePalette512];
  const Job512 job{&rig, palette, wide, &out, skip_dual, !out.normal[0].empty() && !rig.normal[0].empty()};
  if (palette.size() > kMaxWidePalette512) return run_lbs_scalar(job, first, count);
  for (size_t j = 0; j < palette.size(); ++j) wide[j] = widen512(palette[j]);
  return dispatch_influences(
      rig.influences_per_vertex,
      [&]<uint32_t K>() { return run_lbs_blocks<&linear_vertex_512<K>, &flush_normals>(job, first, count); },
      [&] { return run_lbs_scalar(job, first, count); });
}

}  // namespace sinew::skin::detail

SINEW_ISA_END
