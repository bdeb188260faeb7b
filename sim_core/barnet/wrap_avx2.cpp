// AVX2 kernels of the bar-net wrap (wrap.hpp), with the same output words as
// the scalar specification (wrap.cpp) for every input. Their functions are
// compiled for AVX2 (isa_region.hpp), on x86-64 only; called only when the
// CPU reports AVX2.
//   - Triangle frames in two passes: the corners and the specification's
//     floor-shifted cross product (shifted_cross) per triangle, then those
//     normalised four at a time by fx::avx2::normalize_fast_x4
//     (fx::normalize_fast's words). Apart, each pass's iterations are short
//     and independent, and the normalisations' long chains of dependent
//     products overlap.
//   - The bounded wrap, one vertex per step with x, y and z in three
//     64-bit lanes: the four terms d n_c + sum_k b_k c_k as vpmuldq products
//     of int32 values, the plain int64 sums of the specification's bounded
//     path (no overflow there). A vertex whose sum rounds beyond int32 makes
//     the kernel return false, and the caller then wraps every vertex by the
//     specification, saturation count included.
#include <immintrin.h>

#include <cstring>

#include "sim_core/fixed/avx2_lanes.hpp"
#include "sim_core/fixed/isa_region.hpp"
#include "wrap.hpp"

SINEW_ISA_BEGIN("avx2")

namespace sinew::barnet::detail {
namespace {

constexpr uint32_t kLanes = 4;

inline __m256i mul(__m256i a, __m256i b) { return _mm256_mul_epi32(a, b); }

inline fx::Vec3 node_at(const std::span<fx::Len> (&node)[3], uint32_t i) {
  return {node[0][i], node[1][i], node[2][i]};
}

// Four words of a frame from byte `offset` on, sign-extended to int64 lanes.
inline __m256i frame_words(const TriangleFrame& f, size_t offset) {
  static_assert(sizeof(TriangleFrame) == 13 * sizeof(int32_t));
  __m128i x;
  std::memcpy(&x, reinterpret_cast<const unsigned char*>(&f) + offset, sizeof(x));
  return _mm256_cvtepi32_epi64(x);
}

// Every |node[c][i]| < 2^30 for i < count: then an edge b - a fits int32,
// and fx::sub's saturation cannot act. Eight lanes at a time.
bool nodes_below_2_30(const std::span<fx::Len> (&node)[3], size_t count) {
  constexpr int32_t kLimit = (int32_t{1} << 30) - 1;
  const __m256i hi = _mm256_set1_epi32(kLimit), lo = _mm256_set1_epi32(-kLimit);
  __m256i outside = _mm256_setzero_si256();
  bool scalar_outside = false;
  for (const std::span<fx::Len>& axis : node) {
    size_t i = 0;
    for (; i + 8 <= count; i += 8) {
      __m256i v;
      std::memcpy(&v, axis.data() + i, sizeof(v));
      outside = _mm256_or_si256(outside, _mm256_or_si256(_mm256_cmpgt_epi32(v, hi), _mm256_cmpgt_epi32(lo, v)));
    }
    for (; i < count; ++i) scalar_outside |= axis[i] > kLimit || axis[i] < -kLimit;
  }
  return !scalar_outside && _mm256_testz_si256(outside, outside) != 0;
}

template <bool kSmall>
inline fx::Vec3 edge(fx::Vec3 from, fx::Vec3 to) {
  if constexpr (kSmall) return {to.x - from.x, to.y - from.y, to.z - from.z};  // |.| <= 2^31 - 2
  return fx::sub(to, from);
}

// Pass 1 of the frames, one triangle at a time: the corners, and the
// floor-shifted cross product (below 2^31 per component) in the normal's
// place. kSmall: every node below 2^30 in magnitude (nodes_below_2_30).
template <bool kSmall>
void corners_and_crosses(const BarnetModel& m, const std::span<fx::Len> (&node)[3], std::span<TriangleFrame> frames) {
  const uint32_t count = static_cast<uint32_t>(m.triangles.size());
  for (uint32_t t = 0; t < count; ++t) {
    const ControlTriangle& tri = m.triangles[t];
    TriangleFrame& f = frames[t];
    // From locals, not from the frame just written: two narrow stores do
    // not forward to the wide load that passes a Vec3 in registers.
    const fx::Vec3 a = node_at(node, tri.node[0]), b = node_at(node, tri.node[1]), c = node_at(node, tri.node[2]);
    f.corner[0] = a, f.corner[1] = b, f.corner[2] = c;
    f.normal = shifted_cross_of_edges(edge<kSmall>(a, b), edge<kSmall>(a, c));
    f.pad = 0;
  }
}

}  // namespace

void corners_and_crosses_avx2(const BarnetModel& m, const std::span<fx::Len> (&node)[3],
                              std::span<TriangleFrame> frames) {
  if (nodes_below_2_30(node, m.nodes.size()))
    corners_and_crosses<true>(m, node, frames);
  else
    corners_and_crosses<false>(m, node, frames);
}

void make_triangle_frames_avx2(const BarnetModel& m, const std::span<fx::Len> (&node)[3],
                               std::span<TriangleFrame> frames) {
  const uint32_t count = static_cast<uint32_t>(m.triangles.size());
  corners_and_crosses_avx2(m, node, frames);
  // Pass 2, four triangles per group (a last group of fewer repeats its last
  // triangle in the spare lanes and stores only the real ones): each
  // shifted product normalised in place.
  for (uint32_t first = 0; first < count; first += kLanes) {
    const uint32_t n = count - first < kLanes ? count - first : kLanes;
    __m128i row[kLanes];  // x, y, z, pad of one triangle's shifted product
    for (uint32_t l = 0; l < kLanes; ++l)
      std::memcpy(&row[l], &frames[first + (l < n ? l : n - 1)].normal, sizeof(row[l]));
    // Transposed: component c of the four triangles, sign-extended to int64.
    const __m128i xy01 = _mm_unpacklo_epi32(row[0], row[1]), xy23 = _mm_unpacklo_epi32(row[2], row[3]);
    const __m128i zp01 = _mm_unpackhi_epi32(row[0], row[1]), zp23 = _mm_unpackhi_epi32(row[2], row[3]);
    __m256i unit[3];
    fx::avx2::normalize_fast_x4(_mm256_cvtepi32_epi64(_mm_unpacklo_epi64(xy01, xy23)),
                                _mm256_cvtepi32_epi64(_mm_unpackhi_epi64(xy01, xy23)),
                                _mm256_cvtepi32_epi64(_mm_unpacklo_epi64(zp01, zp23)), unit);
    int64_t w[3][kLanes];
    for (int c = 0; c < 3; ++c) fx::avx2::lanes(unit[c], w[c]);
    for (uint32_t l = 0; l < n; ++l)
      frames[first + l].normal = {static_cast<int32_t>(w[0][l]), static_cast<int32_t>(w[1][l]),
                                  static_cast<int32_t>(w[2][l])};
  }
}

bool wrap_bounded_avx2(const BarnetModel& m, std::span<const TriangleFrame> frames,
                       const std::span<fx::Len> (&skin)[3]) {
  // v + 2^29 rounds half up; + 2^61 maps the int32 results' window
  // [-2^61, 2^61) of v + 2^29 onto [0, 2^62), so bits 62 and 63 flag a
  // vertex beyond int32, and bits 30..61 hold the result plus 2^31.
  const __m256i bias = _mm256_set1_epi64x((int64_t{1} << 29) + (int64_t{1} << 61));
  const __m256i xyz = _mm256_setr_epi64x(-1, -1, -1, 0);  // the fourth lane reads the next word: not a result
  const __m256i half = _mm256_set1_epi64x(int64_t{1} << 31);
  const __m256i pack = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
  fx::Len* const out[3] = {skin[0].data(), skin[1].data(), skin[2].data()};
  __m256i beyond = _mm256_setzero_si256();
  const uint32_t count = static_cast<uint32_t>(m.wrap.size());
  for (uint32_t w = 0; w < count; ++w) {
    const WrapRecord& r = m.wrap[w];
    const TriangleFrame& f = frames[r.triangle];
    // vpmuldq reads the low 32 bits of each lane: 32-bit broadcasts suffice.
    __m256i acc = mul(frame_words(f, offsetof(TriangleFrame, normal)), _mm256_set1_epi32(r.offset));
    for (uint32_t k = 0; k < 3; ++k)
      acc = _mm256_add_epi64(acc, mul(frame_words(f, k * sizeof(fx::Vec3)), _mm256_set1_epi32(r.bary[k])));
    const __m256i biased = _mm256_add_epi64(acc, bias);
    beyond = _mm256_or_si256(beyond, _mm256_and_si256(_mm256_srli_epi64(biased, 62), xyz));
    const __m256i value = _mm256_xor_si256(_mm256_srli_epi64(biased, 30), half);
    const __m128i v = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(value, pack));
    out[0][w] = _mm_cvtsi128_si32(v);
    out[1][w] = _mm_extract_epi32(v, 1);
    out[2][w] = _mm_extract_epi32(v, 2);
  }
  return _mm256_testz_si256(beyond, beyond) != 0;
}

}  // namespace sinew::barnet::detail

SINEW_ISA_END
