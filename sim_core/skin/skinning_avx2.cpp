// AVX2 kernel of linear blend skinning: the same output words and the same
// saturation count as the scalar specification (skinning.cpp) for every input.
// Built with -mavx2 for this file only, and only on x86-64; called only when
// the CPU reports AVX2 (skinning.cpp).
//
// One vertex per step, one 64-bit lane per row of the blended transform:
//   - per call, the palette is rearranged ("widened") into columns, two
//     columns interleaved per 256-bit word, so vpmuldq reads one column from
//     the even 32-bit halves and the next one after a 32-bit shift;
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
//     as sat_i32 does.
// DQS vertices, palettes larger than the widened buffer and K outside 1..8
// take the scalar specification.
#include <immintrin.h>

#include <cstring>

#include "sim_core/fixed/rsqrt_fast.hpp"
#include "skinning_detail.hpp"

namespace sinew::skin::detail {
namespace {

// Palettes up to this size are widened on the stack (64 bytes per entry).
constexpr size_t kMaxWidePalette = 256;

// Columns of one palette entry: lo holds the linear columns 0 and 1, hi the
// linear column 2 and the translation, interleaved by 32-bit halves; lane r
// of each column is row r, lane 3 is zero.
struct WideEntry {
  __m256i lo;
  __m256i hi;
};

inline WideEntry widen(const fx::Mat34& m) {
  return {_mm256_setr_epi32(m.m[0][0], m.m[0][1], m.m[1][0], m.m[1][1], m.m[2][0], m.m[2][1], 0, 0),
          _mm256_setr_epi32(m.m[0][2], m.t[0], m.m[1][2], m.t[1], m.m[2][2], m.t[2], 0, 0)};
}

// round_shift(x, s) of scalar.hpp on every int64 lane: ((x + 2^(s-1) + 2^63)
// >>> s) - 2^(63-s), with wrapping vector adds (no UB, same bits).
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

// Row-wise M v for a broadcast vector v and the blended columns (Q8.24), in
// the vector's format times 2^24 (not yet rounded).
inline __m256i apply_linear(const __m256i col[3], int32_t v0, int32_t v1, int32_t v2) {
  __m256i acc = _mm256_mul_epi32(col[0], _mm256_set1_epi64x(v0));
  acc = _mm256_add_epi64(acc, _mm256_mul_epi32(col[1], _mm256_set1_epi64x(v1)));
  return _mm256_add_epi64(acc, _mm256_mul_epi32(col[2], _mm256_set1_epi64x(v2)));
}

struct Job {
  const rig::Rig* rig;
  std::span<const fx::Mat34> palette;
  std::span<const fx::DualQuat> dual;
  const WideEntry* wide;
  const SkinnedVertices* out;
  bool dual_ready;
  bool normals;
};

// One LBS vertex; false if its blended linear part might clamp (then nothing
// was written and the caller runs the scalar specification).
template <uint32_t K>
inline bool linear_vertex(const Job& job, uint32_t v, uint32_t index) {
  const rig::Rig& rig = *job.rig;
  const uint16_t* joints = rig.influence_palette.data() + size_t{v} * K;
  const fx::Unit* weights = rig.influence_weight.data() + size_t{v} * K;
  __m256i acc[4] = {_mm256_setzero_si256(), _mm256_setzero_si256(), _mm256_setzero_si256(),
                    _mm256_setzero_si256()};
  for (uint32_t k = 0; k < K; ++k) {
    const WideEntry& e = job.wide[joints[k]];
    const __m256i w = _mm256_set1_epi64x(weights[k]);
    acc[0] = _mm256_add_epi64(acc[0], _mm256_mul_epi32(e.lo, w));
    acc[1] = _mm256_add_epi64(acc[1], _mm256_mul_epi32(_mm256_srli_epi64(e.lo, 32), w));
    acc[2] = _mm256_add_epi64(acc[2], _mm256_mul_epi32(e.hi, w));
    acc[3] = _mm256_add_epi64(acc[3], _mm256_mul_epi32(_mm256_srli_epi64(e.hi, 32), w));
  }
  // Q2.30 x Q8.24 -> Q8.24. The scalar path clamps to [-2^30, 2^30]; here
  // [-2^30, 2^30) is proven clamp-free, anything else (including exactly +64)
  // goes back to the specification.
  __m256i col[3];
  for (int c = 0; c < 3; ++c) {
    col[c] = round_shift_epi64<fx::kUnitFracBits>(acc[c]);
    if (!all_in_window<31>(col[c], -(int64_t{1} << 30))) return false;
  }
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
    fx::Vec3 unit;
    fx::normalize_fast({static_cast<int32_t>(r[0]), static_cast<int32_t>(r[1]), static_cast<int32_t>(r[2])}, &unit);
    out.normal[0][index] = unit.x;
    out.normal[1][index] = unit.y;
    out.normal[2][index] = unit.z;
  }
  return true;
}

template <uint32_t K>
uint32_t run(const Job& job, uint32_t first, uint32_t count) {
  const rig::Rig& rig = *job.rig;
  uint32_t saturated = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t v = first + i;
    if (job.dual_ready && rig.method[v] == static_cast<uint8_t>(rig::SkinMethod::kDualQuaternion)) {
      skin_dual_vertex(rig, job.dual, v, *job.out, i);
    } else if (!linear_vertex<K>(job, v, i)) {
      skin_linear_vertex(rig, job.palette, v, *job.out, i, &saturated);
    }
  }
  return saturated;
}

// The scalar loop of skinning.cpp, for inputs the vector path does not take.
uint32_t run_scalar(const Job& job, uint32_t first, uint32_t count) {
  uint32_t saturated = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t v = first + i;
    if (job.dual_ready && job.rig->method[v] == static_cast<uint8_t>(rig::SkinMethod::kDualQuaternion)) {
      skin_dual_vertex(*job.rig, job.dual, v, *job.out, i);
    } else {
      skin_linear_vertex(*job.rig, job.palette, v, *job.out, i, &saturated);
    }
  }
  return saturated;
}

}  // namespace

uint32_t skin_vertices_avx2(const rig::Rig& rig, std::span<const fx::Mat34> palette,
                            std::span<const fx::DualQuat> dual_palette, uint32_t first, uint32_t count,
                            const SkinnedVertices& out) {
  WideEntry wide[kMaxWidePalette];
  const Job job{&rig,
                palette,
                dual_palette,
                wide,
                &out,
                !dual_palette.empty(),
                !out.normal[0].empty() && !rig.normal[0].empty()};
  if (palette.size() > kMaxWidePalette) return run_scalar(job, first, count);
  for (size_t j = 0; j < palette.size(); ++j) wide[j] = widen(palette[j]);
  switch (rig.influences_per_vertex) {
    case 1: return run<1>(job, first, count);
    case 2: return run<2>(job, first, count);
    case 3: return run<3>(job, first, count);
    case 4: return run<4>(job, first, count);
    case 5: return run<5>(job, first, count);
    case 6: return run<6>(job, first, count);
    case 7: return run<7>(job, first, count);
    case 8: return run<8>(job, first, count);
    default: return run_scalar(job, first, count);
  }
}

}  // namespace sinew::skin::detail
