// AVX2 kernel of the normal-ball deformation, eq. (4) of
// metaballs-pbd-skinning with the balls' rotations blended before they act
// (deform.cpp): the same output words as the scalar specification
// (deform_normal_ball_vertex) for every input. Built with -mavx2 for this
// file only, on x86-64 only; called only when the CPU reports AVX2.
//
// One vertex per step, one 64-bit lane per coordinate (lane 3 unused):
//   - per step, each ball's rotation columns, centre and bulge scale are
//     widened once into sign-extended 64-bit lanes on the stack (192 bytes a
//     ball, up to kMaxWideBalls = 256: 48 KiB; more balls decline to the
//     scalar loop);
//   - the vertex's rotation is the specification's (vertex_rotation): the
//     shared ball's widened rotation, or the blend of its balls' rotations;
//   - sum w c and sum w (s d) are sums of exact vpmuldq products in 64-bit
//     lanes: exactly the scalar int64 sums, so s d must fit int32: it does for
//     every validated model (|d| <= 2^30, s < 2), and a vertex where it would
//     not is redone by the specification; where no weighted ball is scaled,
//     sum w d is the state's rounded blend made at init (vertex_rest_disp);
//   - a vertex whose weighted balls all follow one bone alone turns alike
//     without comparing their rotations, when every such ball's rotation is
//     its bone's (checked once a call: one_bone_balls_follow_bones);
//   - R D is three vpmuldq products summed in 64-bit lanes: exactly the
//     scalar int64 sums of rotate_q50;
//   - round half up is (x + 2^(s-1)) >> s with the arithmetic shift built
//     from a logical one on x + 2^63 (AVX2 has no 64-bit arithmetic shift):
//     exact for every int64;
//   - saturation to int32 is sat_i32's.
#include <immintrin.h>

#include <cstring>

#include "kernels.hpp"

namespace sinew::metaballs::detail {
namespace {

constexpr uint32_t kMaxWideBalls = 256;

struct WideBall {
  __m256i col[3];  // rotation column j, rows in lanes 0..2
  __m256i center;  // Len, lanes 0..2
  __m256i scale;   // Q2.30 in every lane (vpmuldq reads the low half)
  bool scaled;     // scale != 1: the bulge rounding applies (192 bytes a ball with padding)
};

inline WideBall widen_ball(const fx::Rot3& r, fx::Vec3 c, fx::Unit scale) {
  WideBall b{};
  for (int j = 0; j < 3; ++j) b.col[j] = _mm256_setr_epi64x(r.m[0][j], r.m[1][j], r.m[2][j], 0);
  b.center = _mm256_setr_epi64x(c.x, c.y, c.z, 0);
  b.scale = _mm256_set1_epi64x(scale);
  b.scaled = scale != fx::kUnitOne;
  return b;
}

// fx::round_shift(x, S) on every int64 lane.
template <int S>
inline __m256i round_shift_lanes(__m256i x) {
  const __m256i bias = _mm256_set1_epi64x(INT64_MIN + (int64_t{1} << (S - 1)));
  const __m256i offset = _mm256_set1_epi64x(int64_t{1} << (63 - S));
  return _mm256_sub_epi64(_mm256_srli_epi64(_mm256_add_epi64(x, bias), S), offset);
}

// True if every lane lies in the int32 range.
inline bool lanes_fit_i32(__m256i x) {
  const __m256i above = _mm256_srli_epi64(_mm256_sub_epi64(x, _mm256_set1_epi64x(INT32_MIN)), 32);
  return _mm256_testz_si256(above, above) != 0;
}

// fx::sat_i32 on every int64 lane (the result still in int64 lanes).
inline __m256i saturate_i32_lanes(__m256i x) {
  if (lanes_fit_i32(x)) return x;
  const __m256i hi = _mm256_set1_epi64x(INT32_MAX);
  const __m256i lo = _mm256_set1_epi64x(INT32_MIN);
  x = _mm256_blendv_epi8(x, hi, _mm256_cmpgt_epi64(x, hi));
  return _mm256_blendv_epi8(x, lo, _mm256_cmpgt_epi64(lo, x));
}

// A rotation's columns in 64-bit lanes.
struct WideRotation {
  __m256i col[3];
};

inline WideRotation widen_rotation(const fx::Rot3& r) {
  WideRotation w;
  for (int j = 0; j < 3; ++j) w.col[j] = _mm256_setr_epi64x(r.m[0][j], r.m[1][j], r.m[2][j], 0);
  return w;
}

// The vertex at v; false (nothing written) when it has no weight or a scaled
// displacement leaves the int32 range, for the caller to run the
// specification. The rotation is the shared ball's (widened once a step) or
// the vertex's blend (vertex_rotation, widened here). alike: the caller
// knows the vertex's balls turn alike (balls_turn_alike), so the shared ball
// is its first weighted one, as vertex_rotation would return.
inline bool deform_vertex(const MetaballModel& m, const MetaballState& s, const WideBall* balls, uint32_t v,
                          const skin::SkinnedVertices& out, bool alike) {
  const size_t base = size_t{v} * kVertexBalls;
  __m256i centre = _mm256_setzero_si256();
  bool scaled = false;
  uint16_t first = kNoBall;
  for (uint32_t k = 0; k < kVertexBalls; ++k) {
    const int32_t w = m.vertex_weight[base + k];
    if (w == 0) continue;
    const uint16_t ball = m.vertex_ball[base + k];
    if (first == kNoBall) first = ball;
    const WideBall& b = balls[ball];
    scaled = scaled || b.scaled;
    centre = _mm256_add_epi64(centre, _mm256_mul_epi32(b.center, _mm256_set1_epi32(w)));
  }
  if (first == kNoBall) return false;
  // sat_i32(round(sum w s d)): the state's blend made at init where no
  // weighted ball is scaled (s = 1: s d = d), else summed here.
  fx::Vec3 d = s.vertex_rest_disp[v];
  if (scaled) {
    __m256i disp = _mm256_setzero_si256();
    for (uint32_t k = 0; k < kVertexBalls; ++k) {
      const int32_t w = m.vertex_weight[base + k];
      if (w == 0) continue;
      const WideBall& b = balls[m.vertex_ball[base + k]];
      const fx::Vec3 d0 = m.vertex_disp[base + k];
      __m256i dk = _mm256_setr_epi64x(d0.x, d0.y, d0.z, 0);
      if (b.scaled) {
        dk = round_shift_lanes<fx::kUnitFracBits>(_mm256_mul_epi32(dk, b.scale));
        if (!lanes_fit_i32(dk)) return false;
      }
      disp = _mm256_add_epi64(disp, _mm256_mul_epi32(dk, _mm256_set1_epi32(w)));
    }
    int64_t dl[4];
    const __m256i dr = saturate_i32_lanes(round_shift_lanes<fx::kUnitFracBits>(disp));
    std::memcpy(dl, &dr, sizeof(dl));
    d = {static_cast<int32_t>(dl[0]), static_cast<int32_t>(dl[1]), static_cast<int32_t>(dl[2])};
  }
  fx::Quat quat;
  fx::Rot3 rotation;
  WideRotation blended;
  const uint16_t shared = alike ? first : vertex_rotation(m, s, v, &quat, &rotation);
  const __m256i* col = nullptr;
  if (shared != kNoBall) {
    col = balls[shared].col;
  } else {
    blended = widen_rotation(rotation);
    col = blended.col;
  }
  __m256i rd = _mm256_mul_epi32(col[0], _mm256_set1_epi32(d.x));
  rd = _mm256_add_epi64(rd, _mm256_mul_epi32(col[1], _mm256_set1_epi32(d.y)));
  rd = _mm256_add_epi64(rd, _mm256_mul_epi32(col[2], _mm256_set1_epi32(d.z)));
  const __m256i p = saturate_i32_lanes(
      _mm256_add_epi64(round_shift_lanes<fx::kUnitFracBits>(centre), round_shift_lanes<fx::kUnitFracBits>(rd)));
  int64_t o[4];
  std::memcpy(o, &p, sizeof(o));
  for (int a = 0; a < 3; ++a) out.position[a][v] = static_cast<int32_t>(o[a]);
  return true;
}

}  // namespace

bool deform_normal_balls_avx2(const MetaballModel& m, const MetaballState& s, const skin::SkinnedVertices& out,
                              std::span<const uint32_t> skip, uint32_t begin, uint32_t end,
                              const TurnedVertices* turned) {
  const uint32_t count = m.ball_count();
  if (count > kMaxWideBalls) return false;
  if (end > m.vertex_count) end = m.vertex_count;
  WideBall balls[kMaxWideBalls];
  for (uint32_t b = 0; b < count; ++b) balls[b] = widen_ball(s.ball_rotation[b], s.ball_center[b], s.ball_scale[b]);
  size_t next = first_skip_at(skip, begin);
  const bool follow = turned != nullptr && one_bone_balls_follow_bones(m, s);
  for (uint32_t v = begin; v < end; ++v) {
    if (next < skip.size() && skip[next] == v) {
      ++next;
      continue;
    }
    if (turned != nullptr && !(follow && s.vertex_bone[v] != kNoBall) && !balls_turn_alike(m, s, v)) {
      turned->take(turned->context, v);
      continue;
    }
    if (!deform_vertex(m, s, balls, v, out, turned != nullptr)) deform_normal_ball_vertex(m, s, v, out);
  }
  return true;
}

}  // namespace sinew::metaballs::detail
