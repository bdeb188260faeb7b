// AVX2 kernel of linear blend skinning: the same output words and the same
// saturation count as the scalar specification (skinning.cpp) for every input.
// Its functions are compiled for AVX2 (isa_region.hpp), on x86-64 only;
// called only when the CPU reports AVX2 (skinning.cpp).
//
// One vertex per step, one 64-bit lane per row of the blended transform:
//   - per call, the palette is rearranged ("widened") into sign-extended
//     64-bit columns on the stack (32 KiB for up to 256 entries), so the blend
//     is one vpmuldq and one vpaddq per column and influence;
//   - the blend is exact 32x32->64 products summed in 64-bit lanes, exactly
//     the scalar int64 sums;
//   - round half up is (x + 2^(s-1)) >> s; AVX2 has no 64-bit arithmetic
//     right shift, so x is offset by 2^63 (order-preserving into unsigned),
//     shifted logically and the offset's 2^(63-s) subtracted: exact for every
//     int64;
//   - the per-vertex clamp of the linear part to +-64 and the int32
//     saturations are range-checked in the vector path; a vertex whose linear
//     part might clamp is redone by the scalar specification (which counts
//     it), and positions or normals out of int32 range are saturated exactly
//     as sat_i32 does;
//   - normals are renormalised after each block of 64 vertices, four at a
//     time (lanes = vertices) by the same integer steps as fx::normalize_fast,
//     the last fewer than four by normalize_fast itself.
// Palettes larger than the widened buffer and K outside 1..8 take the scalar
// specification. DQS vertices are skipped (their own kernel writes them).
#include <immintrin.h>

#include "sim_core/fixed/avx2_lanes.hpp"
#include "sim_core/fixed/isa_region.hpp"
#include "skinning_detail.hpp"

SINEW_ISA_BEGIN("avx2")

#include "lbs_blocks.hpp"

namespace sinew::skin::detail {
namespace {

using fx::avx2::lanes;
using fx::avx2::load4_epi64;
using fx::avx2::round_shift_epi64;
using fx::avx2::sat_i32_epi64;

// Palettes up to this size are widened on the stack (128 bytes per entry).
constexpr size_t kMaxWidePalette = 256;

// Columns of one palette entry, sign-extended to 64-bit lanes: the three
// linear columns and the translation; lane r is row r, lane 3 is zero.
struct WideEntry {
  __m256i col[4];
};

inline WideEntry widen(const fx::Mat34& m) {
  return {{_mm256_setr_epi64x(m.m[0][0], m.m[1][0], m.m[2][0], 0),
           _mm256_setr_epi64x(m.m[0][1], m.m[1][1], m.m[2][1], 0),
           _mm256_setr_epi64x(m.m[0][2], m.m[1][2], m.m[2][2], 0), _mm256_setr_epi64x(m.t[0], m.t[1], m.t[2], 0)}};
}

// Row-wise M v for a broadcast vector v and the blended columns (Q8.24), in
// the vector's format times 2^24 (not yet rounded).
// The broadcasts are 32-bit: vpmuldq reads only the low half of each lane.
inline __m256i apply_linear(const __m256i col[3], int32_t v0, int32_t v1, int32_t v2) {
  __m256i acc = _mm256_mul_epi32(col[0], _mm256_set1_epi32(v0));
  acc = _mm256_add_epi64(acc, _mm256_mul_epi32(col[1], _mm256_set1_epi32(v1)));
  return _mm256_add_epi64(acc, _mm256_mul_epi32(col[2], _mm256_set1_epi32(v2)));
}

void finish_normals(const SkinnedVertices& out, PendingNormals* pending) {
  const int32_t* const c[3] = {pending->c[0], pending->c[1], pending->c[2]};
  renormalise_normals_avx2(c, pending->index, pending->count, out);
  pending->count = 0;
}

struct Job {
  const rig::Rig* rig;
  std::span<const fx::Mat34> palette;
  const WideEntry* wide;
  const SkinnedVertices* out;
  bool skip_dual;
  bool normals;
};

// One LBS vertex; false if its blended linear part might clamp (then nothing
// was written and the caller runs the scalar specification).
template <uint32_t K>
inline bool linear_vertex(const Job& job, uint32_t v, uint32_t index, PendingNormals* pending) {
  const rig::Rig& rig = *job.rig;
  const uint16_t* joints = rig.influence_palette.data() + size_t{v} * K;
  const fx::Unit* weights = rig.influence_weight.data() + size_t{v} * K;
  __m256i acc[4] = {_mm256_setzero_si256(), _mm256_setzero_si256(), _mm256_setzero_si256(), _mm256_setzero_si256()};
  for (uint32_t k = 0; k < K; ++k) {
    const WideEntry& e = job.wide[joints[k]];
    const __m256i w = _mm256_set1_epi32(weights[k]);  // vpmuldq reads the low half of each lane
    for (int c = 0; c < 4; ++c) acc[c] = _mm256_add_epi64(acc[c], _mm256_mul_epi32(e.col[c], w));
  }
  // Q2.30 x Q8.24 -> Q8.24. The scalar path clamps to [-2^30, 2^30]; here
  // [-2^30, 2^30) is proven clamp-free, anything else (including exactly +64)
  // goes back to the specification. col holds round_shift(acc, 30) + 2^33
  // (the offset of round_shift_epi64 not yet subtracted): its low 32 bits are
  // the entry itself, all vpmuldq reads.
  const __m256i bias = _mm256_set1_epi64x(INT64_MIN + (int64_t{1} << (fx::kUnitFracBits - 1)));
  const __m256i low = _mm256_set1_epi64x((int64_t{1} << 33) - (int64_t{1} << 30));
  __m256i col[3];
  __m256i outside = _mm256_setzero_si256();
  for (int c = 0; c < 3; ++c) {
    col[c] = _mm256_srli_epi64(_mm256_add_epi64(acc[c], bias), fx::kUnitFracBits);
    outside = _mm256_or_si256(outside, _mm256_sub_epi64(col[c], low));
  }
  outside = _mm256_srli_epi64(outside, 31);
  if (!_mm256_testz_si256(outside, outside)) return false;
  // Translation in Q12.20 (any int64 value; the scalar product t * 2^24 is
  // defined for the same inputs as this shift).
  const __m256i t = _mm256_slli_epi64(round_shift_epi64<fx::kUnitFracBits>(acc[3]), 24);
  const SkinnedVertices& out = *job.out;
  int64_t r[4];
  const __m256i p = _mm256_add_epi64(apply_linear(col, rig.position[0][v], rig.position[1][v], rig.position[2][v]), t);
  lanes(sat_i32_epi64(round_shift_epi64<fx::kLinFracBits>(p)), r);
  for (int i = 0; i < 3; ++i) out.position[i][index] = static_cast<int32_t>(r[i]);
  if (job.normals) {
    const __m256i n = apply_linear(col, rig.normal[0][v], rig.normal[1][v], rig.normal[2][v]);
    lanes(sat_i32_epi64(round_shift_epi64<fx::kLinFracBits>(n)), r);
    const uint32_t slot = pending->count++;
    for (int c = 0; c < 3; ++c) pending->c[c][slot] = static_cast<int32_t>(r[c]);
    pending->index[slot] = index;
  }
  return true;
}

}  // namespace

void renormalise_normals_avx2(const int32_t* const c[3], const uint32_t* index, uint32_t count,
                              const SkinnedVertices& out) {
  uint32_t j = 0;
  for (; j + 4 <= count; j += 4) {
    __m256i unit[3];
    fx::avx2::normalize_fast_x4(load4_epi64(c[0] + j), load4_epi64(c[1] + j), load4_epi64(c[2] + j), unit);
    for (int a = 0; a < 3; ++a) {
      int64_t w[4];
      lanes(unit[a], w);
      for (uint32_t l = 0; l < 4; ++l) out.normal[a][index[j + l]] = static_cast<int32_t>(w[l]);
    }
  }
  for (; j < count; ++j) {  // tail: fewer than 4 left, the scalar function
    fx::Vec3 unit;
    fx::normalize_fast({c[0][j], c[1][j], c[2][j]}, &unit);
    out.normal[0][index[j]] = unit.x;
    out.normal[1][index[j]] = unit.y;
    out.normal[2][index[j]] = unit.z;
  }
}

uint32_t skin_linear_avx2(const rig::Rig& rig, std::span<const fx::Mat34> palette, bool skip_dual, uint32_t first,
                          uint32_t count, const SkinnedVertices& out) {
  WideEntry wide[kMaxWidePalette];
  const Job job{&rig, palette, wide, &out, skip_dual, !out.normal[0].empty() && !rig.normal[0].empty()};
  if (palette.size() > kMaxWidePalette) return run_lbs_scalar(job, first, count);
  for (size_t j = 0; j < palette.size(); ++j) wide[j] = widen(palette[j]);
  return dispatch_influences(
      rig.influences_per_vertex,
      [&]<uint32_t K>() { return run_lbs_blocks<&linear_vertex<K>, &finish_normals>(job, first, count); },
      [&] { return run_lbs_scalar(job, first, count); });
}

}  // namespace sinew::skin::detail

SINEW_ISA_END
