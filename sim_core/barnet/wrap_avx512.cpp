// AVX-512 (F + VL + CD) kernel of the bar-net's triangle frames (wrap.hpp),
// with the same output words as the scalar specification (wrap.cpp) for
// every input. Its functions are compiled for those extensions
// (isa_region.hpp), on x86-64 only; called only when the CPU reports them
// and AVX2 (wrap.cpp).
//
// The frames in the AVX2 kernel's two passes (wrap_avx2.cpp): its first pass
// as it is (corners and floor-shifted cross products, short independent
// iterations), then the shifted products normalised eight at a time by
// fx::avx512::normalize_fast_x8 (fx::normalize_fast's words, zero to zero).
// The eight products are gathered from the frames by 32-bit word index and
// the units scattered back to the same words; a last group of fewer than
// eight runs under a lane mask, so no word past the last frame is read or
// written.

// GCC 12's AVX-512 headers start some intrinsics from _mm512_undefined_*,
// which its -W(maybe-)uninitialized reports wherever they inline (GCC bug
// 105593, fixed in GCC 13): silenced for this file only.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include <immintrin.h>

#include <cstddef>

#include "sim_core/fixed/avx512_lanes.hpp"
#include "sim_core/fixed/isa_region.hpp"
#include "wrap.hpp"

SINEW_ISA_BEGIN("avx512f,avx512vl,avx512cd")

namespace sinew::barnet::detail {
namespace {

constexpr uint32_t kLanes = 8;
constexpr int32_t kFrameWords = sizeof(TriangleFrame) / sizeof(int32_t);  // 13
constexpr int32_t kNormalWord = offsetof(TriangleFrame, normal) / sizeof(int32_t);
static_assert(kFrameWords == 13 && kNormalWord == 9);

}  // namespace

bool make_triangle_frames_avx512(const BarnetModel& m, const std::span<fx::Len> (&node)[3],
                                 std::span<TriangleFrame> frames) {
  const uint32_t count = static_cast<uint32_t>(m.triangles.size());
  // Word indices below 2^31: every frame's last word, lanes included.
  if (uint64_t{count} + kLanes > uint64_t{INT32_MAX} / kFrameWords) return false;
  corners_and_crosses_avx2(m, node, frames);
  int32_t* const words = reinterpret_cast<int32_t*>(frames.data());
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i stride = _mm256_set1_epi32(kFrameWords);
  for (uint32_t first = 0; first < count; first += kLanes) {
    const uint32_t n = count - first < kLanes ? count - first : kLanes;
    const __mmask8 live = static_cast<__mmask8>((1u << n) - 1);
    // Word index of component 0 of each lane's shifted product.
    const __m256i x_word = _mm256_add_epi32(
        _mm256_mullo_epi32(_mm256_add_epi32(_mm256_set1_epi32(static_cast<int32_t>(first)), lane), stride),
        _mm256_set1_epi32(kNormalWord));
    __m512i product[3];
    for (int c = 0; c < 3; ++c) {
      const __m256i index = _mm256_add_epi32(x_word, _mm256_set1_epi32(c));
      // Dead lanes read nothing and stay zero: their (zero) units are not stored.
      const __m256i v = _mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), live, index, words, 4);
      product[c] = _mm512_cvtepi32_epi64(v);
    }
    __m512i unit[3];
    fx::avx512::normalize_fast_x8(product[0], product[1], product[2], unit);
    for (int c = 0; c < 3; ++c) {
      const __m256i index = _mm256_add_epi32(x_word, _mm256_set1_epi32(c));
      // The units are within +-2^30: narrowing keeps their words.
      _mm256_mask_i32scatter_epi32(words, live, index, _mm512_cvtepi64_epi32(unit[c]), 4);
    }
  }
  return true;
}

}  // namespace sinew::barnet::detail

SINEW_ISA_END
