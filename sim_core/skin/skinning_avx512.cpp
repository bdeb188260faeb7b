// AVX-512 (F + VL + CD) kernel of linear blend skinning: the same output words
// and the same saturation count as the scalar specification (skinning.cpp)
// for every input. Its functions are compiled for those extensions
// (isa_region.hpp), on x86-64 only; called only when the CPU reports all
// three (skinning.cpp).
//
// One vertex per step, the twelve entries of the blended transform in two
// 512-bit registers of 64-bit lanes:
//   - per call, the palette is widened once: entry j becomes [column 0 |
//     column 1] and [column 2 | translation], each half three rows and a zero
//     lane, so the blend is two vpmuldq and two vpaddq per influence (the
//     AVX2 kernel needs four of each), exact 32x32->64 products summed as the
//     scalar int64 sums;
//   - round half up is (x >> s) + ((x >> (s-1)) & 1) with vpsraq: exact for
//     every int64, no offset;
//   - the linear part's range check is mask compares against [-2^30, 2^30],
//     where the scalar clamp is the identity; a vertex outside is redone by
//     the specification, which counts the clamp;
//   - the position and the unnormalised normal are formed in one register
//     ([R p + t | R n], 128-bit lane shuffles add the column products), then
//     rounded, saturated (vpmaxsq, vpminsq) and narrowed together;
//   - normals are renormalised after each block, eight at a time (lanes =
//     vertices) by the integer steps of fx::normalize_fast with vplzcntq
//     (avx512_lanes.hpp).
// Palettes larger than the widened buffer and K outside 1..8 take the scalar
// specification; DQS vertices are skipped (their own kernel writes them).
// GCC 12's AVX-512 headers start some intrinsics from _mm512_undefined_*,
// which its -W(maybe-)uninitialized reports wherever they inline (GCC bug
// 105593, fixed in GCC 13): silenced for this file only.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <immintrin.h>

#include <cstring>

#include "sim_core/fixed/avx512_lanes.hpp"
#include "sim_core/fixed/isa_region.hpp"
#include "skinning_detail.hpp"

SINEW_ISA_BEGIN("avx512f,avx512vl,avx512cd")

#include "lbs_blocks.hpp"

namespace sinew::skin::detail {
namespace {

using fx::avx512::round_shift_epi64;
using fx::avx512::sat_i32_epi64;

constexpr size_t kMaxWidePalette512 = 256;  // 128 bytes per entry on the stack

// Lanes 0..2 column 0 (rows 0..2), 4..6 column 1; lanes 3 and 7 zero.
// second: column 2 and the translation the same way.
struct WideEntry512 {
  __m512i first, second;
};

inline WideEntry512 widen512(const fx::Mat34& m) {
  return {_mm512_setr_epi64(m.m[0][0], m.m[1][0], m.m[2][0], 0, m.m[0][1], m.m[1][1], m.m[2][1], 0),
          _mm512_setr_epi64(m.m[0][2], m.m[1][2], m.m[2][2], 0, m.t[0], m.t[1], m.t[2], 0)};
}

// a in lanes 0..3, b in lanes 4..7, for vpmuldq (which reads the low half
// of each 64-bit lane).
inline __m512i halves(int32_t a, int32_t b) { return _mm512_mask_set1_epi32(_mm512_set1_epi32(a), 0xFF00, b); }

void flush_normals(const SkinnedVertices& out, PendingNormals* pending) {
  const uint32_t count = pending->count;
  for (uint32_t j = 0; j < count; j += 8) {
    const uint32_t n = count - j < 8 ? count - j : 8;
    const __mmask8 live = static_cast<__mmask8>((1u << n) - 1);  // the rest load as zero vectors
    __m512i c[3];
    for (int a = 0; a < 3; ++a) c[a] = _mm512_cvtepi32_epi64(_mm256_maskz_loadu_epi32(live, pending->c[a] + j));
    __m512i unit[3];
    fx::avx512::normalize_fast_x8(c[0], c[1], c[2], unit);
    const uint32_t* index = pending->index + j;
    const bool contiguous = n == 8 && index[7] - index[0] == 7;  // ascending, so 8 in a row
    for (int a = 0; a < 3; ++a) {
      const __m256i words = _mm512_cvtepi64_epi32(unit[a]);  // in int32 range: sat_i32 applied
      if (contiguous) {
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out.normal[a].data() + index[0]), words);
      } else {
        int32_t w[8];
        std::memcpy(w, &words, sizeof(w));
        for (uint32_t l = 0; l < n; ++l) out.normal[a][index[l]] = w[l];
      }
    }
  }
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
  __m512i acc0 = _mm512_setzero_si512(), acc1 = _mm512_setzero_si512();
  for (uint32_t k = 0; k < K; ++k) {
    const WideEntry512& e = job.wide[joints[k]];
    const __m512i w = _mm512_set1_epi32(weights[k]);
    acc0 = _mm512_add_epi64(acc0, _mm512_mul_epi32(e.first, w));
    acc1 = _mm512_add_epi64(acc1, _mm512_mul_epi32(e.second, w));
  }
  // Q2.30 x Q8.24 -> Q8.24 (columns) and Q2.30 x Q12.20 -> Q12.20 (translation).
  const __m512i cols01 = round_shift_epi64<fx::kUnitFracBits>(acc0);
  const __m512i col2_t = round_shift_epi64<fx::kUnitFracBits>(acc1);
  const __m512i lo = _mm512_set1_epi64(-(int64_t{1} << 30)), hi = _mm512_set1_epi64(int64_t{1} << 30);
  const __mmask8 outside = _mm512_cmp_epi64_mask(cols01, lo, _MM_CMPINT_LT) |
                           _mm512_cmp_epi64_mask(cols01, hi, _MM_CMPINT_NLE) |
                           _mm512_mask_cmp_epi64_mask(0x0F, col2_t, lo, _MM_CMPINT_LT) |
                           _mm512_mask_cmp_epi64_mask(0x0F, col2_t, hi, _MM_CMPINT_NLE);
  if (outside != 0) return false;
  // [c0 px | c1 py] + [c2 pz | t * 2^24], the scalar sum split in two halves.
  const __m512i p = _mm512_add_epi64(
      _mm512_mul_epi32(cols01, halves(rig.position[0][v], rig.position[1][v])),
      _mm512_mask_slli_epi64(_mm512_mul_epi32(col2_t, _mm512_set1_epi32(rig.position[2][v])), 0xF0, col2_t, 24));
  __m512i n = _mm512_setzero_si512();
  if (job.normals)
    n = _mm512_add_epi64(_mm512_mul_epi32(cols01, halves(rig.normal[0][v], rig.normal[1][v])),
                         _mm512_maskz_mul_epi32(0x0F, col2_t, _mm512_set1_epi32(rig.normal[2][v])));
  // [p.lo | n.lo] + [p.hi | n.hi] = [R p + t | R n], both in Q.(frac + 24).
  const __m512i sum = _mm512_add_epi64(_mm512_shuffle_i64x2(p, n, _MM_SHUFFLE(1, 0, 1, 0)),
                                       _mm512_shuffle_i64x2(p, n, _MM_SHUFFLE(3, 2, 3, 2)));
  const __m256i words = _mm512_cvtepi64_epi32(sat_i32_epi64(round_shift_epi64<fx::kLinFracBits>(sum)));
  int32_t r[8];
  std::memcpy(r, &words, sizeof(r));
  const SkinnedVertices& out = *job.out;
  for (int i = 0; i < 3; ++i) out.position[i][index] = r[i];
  if (job.normals) {
    const uint32_t slot = pending->count++;
    for (int c = 0; c < 3; ++c) pending->c[c][slot] = r[4 + c];
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
