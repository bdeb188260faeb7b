// AVX2 kernel of blend_joint_region_entry (deform.cpp): eq. (5) blended with
// eq. (1) for four joint-region entries at once, with the same output words
// as the scalar specification for every input. Its functions are compiled
// for AVX2 (isa_region.hpp), on x86-64 only; called only when the CPU
// reports AVX2 (deform.cpp).
//
// One entry per 64-bit lane (a last group of fewer repeats its last entry in
// the spare lanes and stores only the real ones):
//   - nlerp_fast's three cases (an end or equal rotations: an input as it is;
//     otherwise the renormalised blend) are all computed and selected per
//     lane; the blend's hemisphere test is the plain dot, exact for near-unit
//     inputs;
//   - every product is a vpmuldq of two int32 values (the scalar 32x32->64
//     product), every sum exact as the scalar's, every sat_i32 the exact lane
//     saturation; rsqrt_fast and its variable shifts are sim_core/fixed/avx2_lanes.hpp's;
//   - a lane the vector path cannot prove exact goes to the specification
//     after its group is stored: a blend lane whose inputs are not near unit
//     (the plain dot could overflow), whose unnormalised sum leaves int32 or
//     has a squared norm of zero (the specification keeps the first
//     rotation); any lane whose joint-to-centre or displacement difference
//     leaves int32;
//   - w_alpha is validated in (0, 1], and a rotation that rot3_of_unit takes
//     is near unit or the blend's normalised one: where either fails, the
//     specification's own int32 or int64 arithmetic overflows, so no check
//     is made for them.
#include <immintrin.h>

#include <cstring>

#include "joint_lanes_avx2.hpp"
#include "kernels.hpp"
#include "sim_core/fixed/isa_region.hpp"

SINEW_ISA_BEGIN("avx2")

namespace sinew::metaballs::detail {
namespace {

using namespace joint_lanes;  // the lane helpers (joint_lanes_avx2.hpp)

inline __m256i select(__m256i mask, __m256i if_set, __m256i otherwise) {
  return _mm256_blendv_epi8(otherwise, if_set, mask);
}

inline __m256i not_near_unit(const __m256i q[4]) {
  __m256i bad = _mm256_setzero_si256();
  for (int c = 0; c < 4; ++c) bad = _mm256_or_si256(bad, outside(q[c], -kFrameRealLimit, kFrameRealLimit));
  return bad;
}

inline __m256i quat_lanes(const fx::Quat* const q[kLanes], int c) {
  const auto at = [c](const fx::Quat* p) { return int64_t{c == 0 ? p->w : (c == 1 ? p->x : (c == 2 ? p->y : p->z))}; };
  return lanes_of(at(q[0]), at(q[1]), at(q[2]), at(q[3]));
}

// Four entries (n real, the spare lanes repeat the last) through the
// stages: the rotations' blend, its inverse norm, then the rest.
struct BlendGroup {
  const NormalBallFrame* f[kLanes];
  const fx::Quat* eta[kLanes];
  uint32_t i[kLanes];
  uint32_t n;
  __m256i a[4], b[4], q[4];  // R_lambda, R_eta, their unnormalised blend
  __m256i alpha, keep_a, take_b, bad, n2;
  fx::avx2::RsqrtX4 rs;
};

// Stage 1: nlerp_fast(a, b, alpha)'s cases and its unnormalised blend: a at
// alpha = 0 or a == b, else b at alpha = 1, else (1 - alpha) a + alpha b on
// a's hemisphere.
void blend_rotations(const MetaballModel& m, BlendGroup* g) {
  const __m256i zero = _mm256_setzero_si256();
  const __m256i unit_one = _mm256_set1_epi64x(fx::kUnitOne);
  const fx::Quat* fq[kLanes];
  for (uint32_t l = 0; l < kLanes; ++l) fq[l] = &g->f[l]->quat;
  __m256i* a = g->a;
  __m256i* b = g->b;
  for (int c = 0; c < 4; ++c) a[c] = quat_lanes(fq, c), b[c] = quat_lanes(g->eta, c);
  const __m256i alpha = lanes_of(m.jv_alpha[g->i[0]], m.jv_alpha[g->i[1]], m.jv_alpha[g->i[2]], m.jv_alpha[g->i[3]]);
  __m256i same = _mm256_set1_epi64x(-1);
  for (int c = 0; c < 4; ++c) same = _mm256_and_si256(same, _mm256_cmpeq_epi64(a[c], b[c]));
  const __m256i keep_a = _mm256_or_si256(_mm256_cmpeq_epi64(alpha, zero), same);
  const __m256i take_b = _mm256_andnot_si256(keep_a, _mm256_cmpeq_epi64(alpha, unit_one));
  const __m256i blended = _mm256_andnot_si256(_mm256_or_si256(keep_a, take_b), _mm256_set1_epi64x(-1));
  __m256i blend_bad = _mm256_or_si256(not_near_unit(a), not_near_unit(b));
  const __m256i dot = add(add(mul(a[0], b[0]), mul(a[1], b[1])), add(mul(a[2], b[2]), mul(a[3], b[3])));
  const __m256i negative = negative_lanes(dot);
  const __m256i wb = sub(_mm256_xor_si256(alpha, negative), negative), wa = sub(unit_one, alpha);
  __m256i* q = g->q;
  for (int c = 0; c < 4; ++c) {
    q[c] = round_shift_epi64<fx::kUnitFracBits>(add(mul(wa, a[c]), mul(wb, b[c])));  // QuatBlend::unit: not saturated
    blend_bad = _mm256_or_si256(blend_bad, outside_i32(q[c]));
  }
  __m256i n2 = add(add(mul(q[0], q[0]), mul(q[1], q[1])), add(mul(q[2], q[2]), mul(q[3], q[3])));
  const __m256i n2_zero = _mm256_cmpeq_epi64(n2, zero);
  blend_bad = _mm256_or_si256(blend_bad, n2_zero);  // the first kept: left to the specification
  g->n2 = _mm256_or_si256(n2, _mm256_srli_epi64(n2_zero, 63));
  g->alpha = alpha;
  g->keep_a = keep_a;
  g->take_b = take_b;
  g->bad = _mm256_and_si256(blend_bad, blended);
}

// Stage 2: the blend's reciprocal square root (a long dependency chain: a
// stage of its own, so consecutive groups overlap).
void inverse_norm(BlendGroup* g) { g->rs = fx::avx2::rsqrt_fast_x4(g->n2); }

// Stage 3: the normalised rotation, its matrix, eq. (1)'s centre and
// displacement, the stores of lanes [0, n); returns the lanes the
// specification must redo.
uint32_t finish_entries(const MetaballModel& m, std::span<const fx::Mat34> joint_model, BlendGroup* g, MetaballState* s,
                        const skin::SkinnedVertices& out) {
  const fx::avx2::VarRoundShift by(g->rs.shift);
  __m256i bad = g->bad;
  const __m256i alpha = g->alpha;
  const uint32_t* i = g->i;
  const uint32_t n = g->n;
  __m256i q[4];
  for (int c = 0; c < 4; ++c) {
    const __m256i normalised = sat_i32_epi64(by(mul(g->q[c], g->rs.y)));
    q[c] = select(g->keep_a, g->a[c], select(g->take_b, g->b[c], normalised));
  }

  // fx::rot3_of_unit(q).
  const __m256i one = _mm256_set1_epi64x(int64_t{1} << 60);
  const __m256i xx = mul(q[1], q[1]), yy = mul(q[2], q[2]), zz = mul(q[3], q[3]);
  const __m256i xy = mul(q[1], q[2]), xz = mul(q[1], q[3]), yz = mul(q[2], q[3]);
  const __m256i wx = mul(q[0], q[1]), wy = mul(q[0], q[2]), wz = mul(q[0], q[3]);
  const __m256i rot[3][3] = {{q30(sub(one, twice(add(yy, zz)))), q30(twice(sub(xy, wz))), q30(twice(add(xz, wy)))},
                             {q30(twice(add(xy, wz))), q30(sub(one, twice(add(xx, zz)))), q30(twice(sub(yz, wx)))},
                             {q30(twice(sub(xz, wy))), q30(twice(add(yz, wx))), q30(sub(one, twice(add(xx, yy))))}};

  // Centre and rest displacement blended linearly by alpha.
  const fx::Vec3* d_eta[kLanes];
  const fx::Vec3* laplacian[kLanes];
  const fx::Vec3* d_lambda[kLanes];
  int64_t jt[3][kLanes], fc[3][kLanes];
  for (uint32_t l = 0; l < kLanes; ++l) {
    d_eta[l] = &m.jv_disp[i[l]];
    laplacian[l] = &m.jv_laplacian[i[l]];
    d_lambda[l] = &g->f[l]->disp;
    const fx::Mat34& joint = joint_model[m.joint_balls[m.jv_ball[i[l]]].joint];
    for (int c = 0; c < 3; ++c) jt[c][l] = joint.t[c], fc[c][l] = g->f[l]->centre[c];
  }
  __m256i centre[3], d[3], lap[3];
  for (int c = 0; c < 3; ++c) {
    const __m256i centre_lambda = lanes_of(fc[c][0], fc[c][1], fc[c][2], fc[c][3]);
    const __m256i to_joint = sub(lanes_of(jt[c][0], jt[c][1], jt[c][2], jt[c][3]), centre_lambda);
    const __m256i dl = vec_lanes(d_lambda, c);
    const __m256i to_eta = sub(vec_lanes(d_eta, c), dl);
    bad = _mm256_or_si256(bad, _mm256_or_si256(outside_i32(to_joint), outside_i32(to_eta)));
    centre[c] = add(centre_lambda, round_shift_epi64<fx::kUnitFracBits>(mul(alpha, to_joint)));
    d[c] = sat_i32_epi64(add(dl, round_shift_epi64<fx::kUnitFracBits>(mul(alpha, to_eta))));
    lap[c] = vec_lanes(laplacian, c);
  }
  int64_t position[3][kLanes], posed[3][kLanes];
  for (int r = 0; r < 3; ++r) {
    const __m256i rd = add(add(mul(rot[r][0], d[0]), mul(rot[r][1], d[1])), mul(rot[r][2], d[2]));
    const __m256i rl = add(add(mul(rot[r][0], lap[0]), mul(rot[r][1], lap[1])), mul(rot[r][2], lap[2]));
    fx::avx2::lanes(sat_i32_epi64(add(centre[r], round_shift_epi64<fx::kUnitFracBits>(rd))), position[r]);
    fx::avx2::lanes(q30(rl), posed[r]);
  }
  for (uint32_t l = 0; l < n; ++l) {
    const uint32_t v = m.jv_vertex[i[l]];
    for (int r = 0; r < 3; ++r) out.position[r][v] = static_cast<int32_t>(position[r][l]);
    s->jv_posed_laplacian[i[l]] = {static_cast<int32_t>(posed[0][l]), static_cast<int32_t>(posed[1][l]),
                                   static_cast<int32_t>(posed[2][l])};
  }
  return static_cast<uint32_t>(_mm256_movemask_pd(_mm256_castsi256_pd(bad))) & ((1u << n) - 1);
}

}  // namespace

void blend_joint_region_entries_avx2(const MetaballModel& m, std::span<const fx::Mat34> joint_model,
                                     std::span<const NormalBallFrame* const> frames, std::span<const fx::Quat> eta,
                                     uint32_t first, MetaballState* s, const skin::SkinnedVertices& out) {
  // Up to kGroupsPerBlock groups go through each stage together.
  constexpr uint32_t kGroupsPerBlock = 8;
  BlendGroup groups[kGroupsPerBlock];
  const uint32_t total = static_cast<uint32_t>(frames.size());
  for (uint32_t block = 0; block < total; block += kGroupsPerBlock * kLanes) {
    const uint32_t left = total - block;
    const uint32_t count = left < kGroupsPerBlock * kLanes ? (left + kLanes - 1) / kLanes : kGroupsPerBlock;
    for (uint32_t g = 0; g < count; ++g) {
      BlendGroup& group = groups[g];
      const uint32_t start = block + g * kLanes;
      group.n = total - start < kLanes ? total - start : kLanes;
      for (uint32_t l = 0; l < kLanes; ++l) {
        const uint32_t k = start + (l < group.n ? l : group.n - 1);  // spare lanes: not stored
        group.f[l] = frames[k];
        group.eta[l] = &eta[k];
        group.i[l] = first + k;
      }
      blend_rotations(m, &group);
    }
    for (uint32_t g = 0; g < count; ++g) inverse_norm(&groups[g]);
    for (uint32_t g = 0; g < count; ++g) {
      BlendGroup& group = groups[g];
      uint32_t redo = finish_entries(m, joint_model, &group, s, out);
      while (redo != 0) {
        const uint32_t l = static_cast<uint32_t>(__builtin_ctz(redo));
        redo &= redo - 1;
        blend_joint_region_entry(m, joint_model, *group.f[l], *group.eta[l], group.i[l], s, out);
      }
    }
  }
}

}  // namespace sinew::metaballs::detail

SINEW_ISA_END
