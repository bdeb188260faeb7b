// AVX2 kernel of joint_region_frame (deform.cpp): eq. (4) on the arc, the
// dual-quaternion blend of a vertex's balls' frames, with the same output
// words as the scalar specification for every input. Its functions are
// compiled for AVX2 (isa_region.hpp), on x86-64 only; called only when the
// CPU reports AVX2 (deform.cpp).
//
// Four vertices per group, one per 64-bit lane (a last group of fewer
// repeats its last vertex in the spare lanes and stores only the real ones):
//   - every value is held sign-extended in its lane, and every product is a
//     vpmuldq of two int32 values: the scalar 32x32->64 product. The scalar
//     sums never overflow on the inputs it is defined for, so the wrapping
//     vector adds give their bits;
//   - a weight of 0 adds nothing, so the lane reads its first weighted
//     ball's frame in that slot instead (a zero-weight slot's ball index is
//     not checked by validation);
//   - the hemisphere test is the plain dot with the first weighted ball,
//     exact when every frame is near unit (make_ball_frames checks it once a
//     step; otherwise the whole batch takes the specification);
//   - every sat_i32 of the specification is fx::avx2::sat_i32_epi64 (exact), and
//     rsqrt_fast and its variable shifts are sim_core/fixed/avx2_lanes.hpp's;
//   - a lane the vector path cannot prove exact goes to the specification
//     after its group is stored: no weighted ball, a negative weight, a
//     scaled displacement s d outside int32, or a squared norm that takes
//     fx::normalize's division path (zero or above 2^63).
#include <immintrin.h>

#include <cstring>

#include "joint_lanes_avx2.hpp"
#include "kernels.hpp"
#include "sim_core/fixed/isa_region.hpp"

SINEW_ISA_BEGIN("avx2")

namespace sinew::metaballs::detail {
namespace {

using namespace joint_lanes;  // the lane helpers (joint_lanes_avx2.hpp)

// Four quaternions, component by component, one per lane.
struct Quat4 {
  __m256i c[4];  // w, x, y, z
};

inline __m256i load_frame(const fx::DualQuat* f) {
  static_assert(sizeof(fx::DualQuat) == sizeof(__m256i));
  __m256i x;
  std::memcpy(&x, f, sizeof(x));
  return x;
}

// (w, x) and (y, z) of one quaternion per lane, from rows holding quaternion
// 0 and 2 (a) and 1 and 3 (b) in their 128-bit halves. (A function, not a
// lambda: GCC compiles lambdas outside the file's AVX2 region.)
inline void split_parts(__m256i a, __m256i b, Quat4* q) {
  const __m256i wx = _mm256_unpacklo_epi64(a, b), yz = _mm256_unpackhi_epi64(a, b);
  q->c[0] = wx, q->c[1] = _mm256_srli_epi64(wx, 32), q->c[2] = yz, q->c[3] = _mm256_srli_epi64(yz, 32);
}

// The real and dual parts of four frames, component c of lane l's frame in
// the low 32 bits of lane l of .c[c] (the high bits are not read: every use
// is a vpmuldq): [real | dual] rows regrouped into [real_0 | real_2] and
// [real_1 | real_3], whose 64-bit unpacks hold (w, x) and (y, z) per lane.
inline void frame_parts(const fx::DualQuat* const f[kLanes], Quat4* real, Quat4* dual) {
  const __m256i f0 = load_frame(f[0]), f1 = load_frame(f[1]), f2 = load_frame(f[2]), f3 = load_frame(f[3]);
  split_parts(_mm256_permute2x128_si256(f0, f2, 0x20), _mm256_permute2x128_si256(f1, f3, 0x20), real);
  split_parts(_mm256_permute2x128_si256(f0, f2, 0x31), _mm256_permute2x128_si256(f1, f3, 0x31), dual);
}

inline __m256i dot4(const Quat4& a, const Quat4& b) {
  return add(add(mul(a.c[0], b.c[0]), mul(a.c[1], b.c[1])), add(mul(a.c[2], b.c[2]), mul(a.c[3], b.c[3])));
}

// Four vertices (n real, the spare lanes repeat the last) through the
// stages: blended, then the inverse norm, then the rest. Components are kept
// as the specification's int64 values, the flags as all-ones lanes.
struct FrameGroup {
  uint32_t v[kLanes];
  uint32_t n;
  uint32_t no_weight;  // lanes with no weighted ball
  __m256i bad;
  Quat4 rq, d;               // DualQuatBlend::unit's parts before fx::normalize_fast
  __m256i rest[3], disp[3];  // q30 of the rest centre and of the displacement blends
  fx::avx2::RsqrtX4 rs;
};

// Stage 1: DualQuatBlend over the vertex's weighted balls, the blended
// scaled displacement, and the parts rounded to Q30 / Len. The rest centre,
// and the displacement of a group whose weighted balls all have scale 1, are
// the state's blends made at init (make_rest_blends): the same words.
void blend_frames(const MetaballModel& m, const MetaballState& s, FrameGroup* g) {
  const __m256i zero = _mm256_setzero_si256();
  __m256i bad = zero;
  // Each lane's slots; its first weighted ball is the pivot of the
  // hemisphere test and the ball read in its zero-weight slots.
  uint16_t ball[kVertexBalls][kLanes];
  int32_t weight[kVertexBalls][kLanes];
  uint16_t pivot_ball[kLanes];
  bool scaled = false;
  g->no_weight = 0;
  for (uint32_t l = 0; l < kLanes; ++l) {
    const size_t base = size_t{g->v[l]} * kVertexBalls;
    pivot_ball[l] = kNoBall;
    for (uint32_t k = 0; k < kVertexBalls; ++k) {
      weight[k][l] = m.vertex_weight[base + k];
      ball[k][l] = m.vertex_ball[base + k];
      if (weight[k][l] == 0) continue;
      if (pivot_ball[l] == kNoBall) pivot_ball[l] = ball[k][l];
      scaled = scaled || s.ball_scale[ball[k][l]] != fx::kUnitOne;
    }
    if (pivot_ball[l] == kNoBall) g->no_weight |= 1u << l, pivot_ball[l] = 0;  // any valid ball; the lane is redone
    for (uint32_t k = 0; k < kVertexBalls; ++k)
      if (weight[k][l] == 0) ball[k][l] = pivot_ball[l];
  }
  const fx::DualQuat* pivot_frame[kLanes];
  for (uint32_t l = 0; l < kLanes; ++l) pivot_frame[l] = &s.ball_frame[pivot_ball[l]];
  Quat4 pivot, unused;
  frame_parts(pivot_frame, &pivot, &unused);

  Quat4 real{{zero, zero, zero, zero}}, dual{{zero, zero, zero, zero}};
  __m256i disp[3] = {zero, zero, zero};
  for (uint32_t k = 0; k < kVertexBalls; ++k) {
    const fx::DualQuat* frame[kLanes];
    for (uint32_t l = 0; l < kLanes; ++l) frame[l] = &s.ball_frame[ball[k][l]];
    const __m256i w = _mm256_cvtepi32_epi64(_mm_loadu_si128(reinterpret_cast<const __m128i*>(weight[k])));
    bad = _mm256_or_si256(bad, negative_lanes(w));
    // DualQuatBlend::add: the weight negated where the frame lies on the
    // other hemisphere from the pivot (dot_negative: the plain dot is exact).
    Quat4 r, e;
    frame_parts(frame, &r, &e);
    const __m256i negative = negative_lanes(dot4(pivot, r));
    const __m256i u = sub(_mm256_xor_si256(w, negative), negative);
    for (int c = 0; c < 4; ++c) {
      real.c[c] = add(real.c[c], mul(u, r.c[c]));
      dual.c[c] = add(dual.c[c], mul(u, e.c[c]));
    }
    if (!scaled) continue;
    const fx::Vec3* d0[kLanes];
    for (uint32_t l = 0; l < kLanes; ++l) d0[l] = &m.vertex_disp[size_t{g->v[l]} * kVertexBalls + k];
    const __m256i scale = lanes_of(s.ball_scale[ball[k][0]], s.ball_scale[ball[k][1]], s.ball_scale[ball[k][2]],
                                   s.ball_scale[ball[k][3]]);
    for (int a = 0; a < 3; ++a) {
      // s d rounded once (at s = 1 exactly d, as the specification's skip).
      const __m256i dd = round_shift_epi64<fx::kUnitFracBits>(mul(vec_lanes(d0, a), scale));
      bad = _mm256_or_si256(bad, outside_i32(dd));
      disp[a] = add(disp[a], mul(w, dd));
    }
  }
  // DualQuatBlend::unit: both parts to Q30 / Len.
  for (int c = 0; c < 4; ++c) g->rq.c[c] = q30(real.c[c]), g->d.c[c] = q30(dual.c[c]);
  const fx::Vec3* rest[kLanes];
  for (uint32_t l = 0; l < kLanes; ++l) rest[l] = &s.vertex_rest_centre[g->v[l]];
  for (int a = 0; a < 3; ++a) g->rest[a] = vec_lanes(rest, a);
  if (scaled) {
    for (int a = 0; a < 3; ++a) g->disp[a] = q30(disp[a]);
  } else {
    const fx::Vec3* unscaled[kLanes];
    for (uint32_t l = 0; l < kLanes; ++l) unscaled[l] = &s.vertex_rest_disp[g->v[l]];
    for (int a = 0; a < 3; ++a) g->disp[a] = vec_lanes(unscaled, a);
  }
  g->bad = bad;
}

// Stage 2: fx::normalize_fast's squared norm and reciprocal square root (a
// long dependency chain: a stage of its own, so consecutive groups overlap).
void inverse_norm(FrameGroup* g) {
  // n2 as uint64 with wrapping adds; n2 - 1 is negative iff n2 == 0 or
  // n2 > 2^63 (fx::normalize's division path).
  __m256i n2 = dot4(g->rq, g->rq);
  g->bad = _mm256_or_si256(g->bad, negative_lanes(sub(n2, _mm256_set1_epi64x(1))));
  n2 = _mm256_or_si256(n2, _mm256_srli_epi64(_mm256_cmpeq_epi64(n2, _mm256_setzero_si256()), 63));  // rsqrt: n2 != 0
  g->rs = fx::avx2::rsqrt_fast_x4(n2);
}

// Stage 3: the rest of fx::normalize_fast, rot3_of_unit and the centre;
// stores lanes [0, n) to frames and returns the lanes the specification
// must redo.
uint32_t finish_frames(FrameGroup* g, NormalBallFrame* frames) {
  Quat4 rq = g->rq, d = g->d;
  const fx::avx2::VarRoundShift by(g->rs.shift);
  for (int c = 0; c < 4; ++c) {
    rq.c[c] = sat_i32_epi64(by(mul(rq.c[c], g->rs.y)));
    d.c[c] = sat_i32_epi64(by(mul(d.c[c], g->rs.y)));
  }
  // rq . d exact (normalize_fast: |rq . d| < 2^63), then the dual part's
  // component along rq removed: sub_sat(d, mul_by_unit(k, rq)).
  const __m256i k = q30(dot4(rq, d));
  for (int c = 0; c < 4; ++c) d.c[c] = sat_i32_epi64(sub(d.c[c], q30(mul(k, rq.c[c]))));

  // fx::rot3_of_unit(rq): e(v) = sat_i32(round_shift(v, 30)).
  const __m256i& qw = rq.c[0];
  const __m256i& qx = rq.c[1];
  const __m256i& qy = rq.c[2];
  const __m256i& qz = rq.c[3];
  const __m256i one = _mm256_set1_epi64x(int64_t{1} << 60);
  const __m256i xx = mul(qx, qx), yy = mul(qy, qy), zz = mul(qz, qz);
  const __m256i xy = mul(qx, qy), xz = mul(qx, qz), yz = mul(qy, qz);
  const __m256i wx = mul(qw, qx), wy = mul(qw, qy), wz = mul(qw, qz);
  const __m256i rot[3][3] = {{q30(sub(one, twice(add(yy, zz)))), q30(twice(sub(xy, wz))), q30(twice(add(xz, wy)))},
                             {q30(twice(add(xy, wz))), q30(sub(one, twice(add(xx, zz)))), q30(twice(sub(yz, wx)))},
                             {q30(twice(sub(xz, wy))), q30(twice(add(yz, wx))), q30(sub(one, twice(add(xx, yy))))}};

  // transform_point_unit(dq, rot, q30(rest)): rotated and moved rounded
  // apart, then added with saturation. t = (dual * conj(real)).xyz in Q50,
  // exact; translation_of's factor 2 follows the rounding, as there.
  const __m256i t[3] = {add(sub(mul(qw, d.c[1]), mul(d.c[0], qx)), sub(mul(qy, d.c[3]), mul(qz, d.c[2]))),
                        add(sub(mul(qw, d.c[2]), mul(d.c[0], qy)), sub(mul(qz, d.c[1]), mul(qx, d.c[3]))),
                        add(sub(mul(qw, d.c[3]), mul(d.c[0], qz)), sub(mul(qx, d.c[2]), mul(qy, d.c[1])))};
  const __m256i(&p)[3] = g->rest;
  __m256i centre[3], out_disp[3];
  for (int i = 0; i < 3; ++i) {
    const __m256i rotated = q30(add(add(mul(rot[i][0], p[0]), mul(rot[i][1], p[1])), mul(rot[i][2], p[2])));
    const __m256i moved = sat_i32_epi64(twice(q30(t[i])));
    centre[i] = sat_i32_epi64(add(rotated, moved));
    out_disp[i] = g->disp[i];
  }

  // Stores: the lanes to int64 arrays, then each real lane's frame.
  int64_t q_lane[4][kLanes], rot_lane[3][3][kLanes], centre_lane[3][kLanes], disp_lane[3][kLanes];
  for (int c = 0; c < 4; ++c) fx::avx2::lanes(rq.c[c], q_lane[c]);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) fx::avx2::lanes(rot[i][j], rot_lane[i][j]);
    fx::avx2::lanes(centre[i], centre_lane[i]);
    fx::avx2::lanes(out_disp[i], disp_lane[i]);
  }
  for (uint32_t l = 0; l < g->n; ++l) {
    NormalBallFrame& f = frames[l];
    for (int i = 0; i < 3; ++i) {
      f.centre[i] = centre_lane[i][l];
      for (int j = 0; j < 3; ++j) f.rotation.m[i][j] = static_cast<int32_t>(rot_lane[i][j][l]);
    }
    f.disp = {static_cast<int32_t>(disp_lane[0][l]), static_cast<int32_t>(disp_lane[1][l]),
              static_cast<int32_t>(disp_lane[2][l])};
    f.quat = {static_cast<int32_t>(q_lane[0][l]), static_cast<int32_t>(q_lane[1][l]),
              static_cast<int32_t>(q_lane[2][l]), static_cast<int32_t>(q_lane[3][l])};
  }
  const uint32_t flagged = static_cast<uint32_t>(_mm256_movemask_pd(_mm256_castsi256_pd(g->bad)));
  return (flagged | g->no_weight) & ((1u << g->n) - 1);
}

}  // namespace

void joint_region_frames_avx2(const MetaballModel& m, const MetaballState& s, std::span<const uint32_t> vertices,
                              std::span<NormalBallFrame> frames) {
  if (!s.ball_frames_near_unit) {
    for (size_t i = 0; i < vertices.size(); ++i) frames[i] = joint_region_frame(m, s, vertices[i]);
    return;
  }
  // Up to kGroupsPerBlock groups go through each stage together.
  constexpr uint32_t kGroupsPerBlock = 8;
  FrameGroup groups[kGroupsPerBlock];
  for (size_t block = 0; block < vertices.size(); block += kGroupsPerBlock * kLanes) {
    const size_t left = vertices.size() - block;
    const uint32_t count =
        static_cast<uint32_t>(left < kGroupsPerBlock * kLanes ? (left + kLanes - 1) / kLanes : kGroupsPerBlock);
    for (uint32_t g = 0; g < count; ++g) {
      const size_t first = block + size_t{g} * kLanes;
      const uint32_t n = static_cast<uint32_t>(vertices.size() - first < kLanes ? vertices.size() - first : kLanes);
      groups[g].n = n;
      for (uint32_t l = 0; l < kLanes; ++l)
        groups[g].v[l] = vertices[first + (l < n ? l : n - 1)];  // spare: not stored
      blend_frames(m, s, &groups[g]);
    }
    for (uint32_t g = 0; g < count; ++g) inverse_norm(&groups[g]);
    for (uint32_t g = 0; g < count; ++g) {
      const size_t first = block + size_t{g} * kLanes;
      uint32_t redo = finish_frames(&groups[g], &frames[first]);
      while (redo != 0) {
        const uint32_t l = static_cast<uint32_t>(__builtin_ctz(redo));
        redo &= redo - 1;
        frames[first + l] = joint_region_frame(m, s, groups[g].v[l]);
      }
    }
  }
}

}  // namespace sinew::metaballs::detail

SINEW_ISA_END
