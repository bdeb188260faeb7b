// NEON kernel of linear blend skinning (AArch64): the same output words and
// the same saturation count as the scalar specification (skinning.cpp) for
// every input. Compiled only for aarch64, where Advanced SIMD is part of the
// base architecture, so skinning.cpp selects it at build time.
//
// One vertex per step, the twelve entries of the blended transform in six
// int64x2 accumulators, in the palette's own row-major order
// {m00 m01}{m02 m10}{m11 m12}{m20 m21}{m22 t0}{t1 t2}:
//   - the blend is exact 32x32->64 products (smlal, vmlal_n_s32) summed in
//     64-bit lanes, straight from the int32 palette (no widened copy), i.e.
//     the scalar int64 sums; the wrapping lane adds give the same value
//     because the scalar sums themselves do not overflow;
//   - round half up is one srshr / srshl: the architecture defines it as
//     (x + 2^(s-1)) >> s evaluated without overflow, which is fx::round_shift
//     for every int64 including negatives and values near INT64_MAX;
//   - int32 saturation of positions and normals is sqxtn (vqmovn_s64), exactly
//     fx::sat_i32;
//   - a vertex whose blended linear part leaves [-64, 64] (so that the clamp,
//     and its saturation count, would act) is redone by the scalar
//     specification; inside that range the clamp is the identity;
//   - the three rows of M v are sums of the same three int64 products as the
//     scalar code, added in another order: the exact total fits int64
//     (|lin| <= 2^30, |v| <= 2^31, 3 * 2^61 + 2^56 < 2^63) and lane adds wrap,
//     so every order gives the scalar value;
//   - normals are renormalised after each block of 64 vertices, two at a time
//     (lanes = vertices), by the same integer steps as fx::normalize_fast; an
//     odd last one fills both lanes.
// DQS vertices are left to the DQS pass; K outside 1..8 takes the scalar specification.
#include <arm_neon.h>

#include <cstring>

#include "lbs_blocks.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"
#include "skinning_detail.hpp"

namespace sinew::skin::detail {
namespace {

static_assert(sizeof(fx::Mat34) == 12 * sizeof(int32_t), "Mat34 is twelve packed int32 words");

// The twelve words of a palette entry, four at a time, in row-major order.
struct EntryWords {
  int32x4_t q[3];  // {m00 m01 m02 m10} {m11 m12 m20 m21} {m22 t0 t1 t2}
};

// Copies of the object representation (well defined for any layout-compatible
// bytes); each compiles to one 128-bit load.
inline EntryWords load_entry(const fx::Mat34& m) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(&m);
  EntryWords e;
  for (int q = 0; q < 3; ++q) std::memcpy(&e.q[q], bytes + 16 * q, sizeof(e.q[q]));
  return e;
}

// Rows of M x for the rounded blended linear part (int32 lanes, in row-major
// order as in EntryWords), in x's format times 2^24, not yet rounded:
// {row0, row1} and {row2, unused}.
struct Rows {
  int64x2_t r01;
  int64x2_t r2;
};

inline Rows apply_linear(int32x4_t lin_a, int32x4_t lin_b, int32x2_t lin_c, int32_t x0, int32_t x1, int32_t x2) {
  const int32x2_t x01 = vset_lane_s32(x1, vdup_n_s32(x0), 1);
  const int32x2_t x22 = vdup_n_s32(x2);
  const int32x2_t x12 = vext_s32(x01, x22, 1);
  const int32x2_t x20 = vext_s32(x22, x01, 1);
  const int64x2_t p0 = vmull_s32(vget_low_s32(lin_a), x01);   // m00 x0, m01 x1
  const int64x2_t p1 = vmull_s32(vget_high_s32(lin_a), x20);  // m02 x2, m10 x0
  const int64x2_t p2 = vmull_s32(vget_low_s32(lin_b), x12);   // m11 x1, m12 x2
  const int64x2_t p3 = vmull_s32(vget_high_s32(lin_b), x01);  // m20 x0, m21 x1
  const int64x2_t p4 = vmull_s32(lin_c, x22);                 // m22 x2, unused
  const int64x2_t r01 = vaddq_s64(vpaddq_s64(p0, p2), p1);
  const int64x2_t r2 = vaddq_s64(vpaddq_s64(p3, vdupq_n_s64(0)), p4);
  return {r01, r2};
}

// fx::normalize_fast on two vectors at once (same words). The Newton steps of
// rsqrt_fast run on unsigned 32-bit lanes: for every reachable v and seed the
// operands and results (y, y^2 >> 30, v y^2 >> 30, 3 * 2^30 - v y^2 >> 30,
// the new y) lie in [0, 2^32) (checked over all 3 * 2^30 values of v), so
// umull and the narrowing shifts are the scalar int64 arithmetic.
inline void normalize_fast_x2(int32x2_t x, int32x2_t y, int32x2_t z, int32x2_t out[3]) {
  // Sum of squares: each <= 2^62, the sum < 2^64 (unsigned, wrapping adds exact).
  uint64x2_t n2 = vaddq_u64(vaddq_u64(vreinterpretq_u64_s64(vmull_s32(x, x)), vreinterpretq_u64_s64(vmull_s32(y, y))),
                            vreinterpretq_u64_s64(vmull_s32(z, z)));
  const uint64x2_t is_zero = vceqzq_u64(n2);
  n2 = vbslq_u64(is_zero, vdupq_n_u64(1), n2);  // any valid lane; zeroed below
  // countl_zero of each 64-bit lane from clz of its 32-bit halves.
  const uint64x2_t halves = vreinterpretq_u64_u32(vclzq_u32(vreinterpretq_u32_u64(n2)));
  const uint64x2_t clz_high = vshrq_n_u64(halves, 32);
  const uint64x2_t clz_low = vandq_u64(halves, vdupq_n_u64(0xFFFFFFFFu));
  const uint64x2_t clz = vaddq_u64(clz_high, vandq_u64(clz_low, vceqq_u64(clz_high, vdupq_n_u64(32))));
  const uint64x2_t s = vandq_u64(clz, vdupq_n_u64(~uint64_t{1}));  // even
  const uint64x2_t m = vshlq_u64(n2, vreinterpretq_s64_u64(s));    // in [2^62, 2^64)
  // Seed table: index (m >> 56) - 64 in [0, 192).
  const uint64x2_t index = vsubq_u64(vshrq_n_u64(m, 56), vdupq_n_u64(64));
  uint32x2_t r = vdup_n_u32(fx::detail::kRsqrtSeed[vgetq_lane_u64(index, 0)]);
  r = vset_lane_u32(fx::detail::kRsqrtSeed[vgetq_lane_u64(index, 1)], r, 1);
  const uint32x2_t v = vshrn_n_u64(m, 32);  // Q30, [2^30, 2^32)
  const uint32x2_t three = vdup_n_u32(uint32_t{3} << 30);
  for (int i = 0; i < 2; ++i) {
    const uint32x2_t r2 = vshrn_n_u64(vmull_u32(r, r), 30);
    const uint32x2_t vr2 = vshrn_n_u64(vmull_u32(v, r2), 30);
    r = vshrn_n_u64(vmull_u32(r, vsub_u32(three, vr2)), 31);
  }
  // c y rounded right by 31 - s / 2 in [0, 31]: srshl by s / 2 - 31 (a shift
  // by 0 adds nothing, as the scalar code's unshifted branch), then sat_i32.
  const int64x2_t shift = vsubq_s64(vreinterpretq_s64_u64(vshrq_n_u64(s, 1)), vdupq_n_s64(31));
  const int32x2_t ry = vreinterpret_s32_u32(r);  // r < 2^31
  const int32x2_t zero_lanes = vreinterpret_s32_u32(vmovn_u64(is_zero));
  const int32x2_t c[3] = {x, y, z};
  for (int i = 0; i < 3; ++i) out[i] = vbic_s32(vqmovn_s64(vrshlq_s64(vmull_s32(c[i], ry), shift)), zero_lanes);
}

void finish_normals(const SkinnedVertices& out, PendingNormals* pending) {
  for (uint32_t j = 0; j < pending->count; j += 2) {
    const uint32_t second = j + 1 < pending->count ? j + 1 : j;  // an odd last one fills both lanes
    int32x2_t c[3];
    for (int i = 0; i < 3; ++i) c[i] = vset_lane_s32(pending->c[i][second], vdup_n_s32(pending->c[i][j]), 1);
    int32x2_t unit[3];
    normalize_fast_x2(c[0], c[1], c[2], unit);
    for (int i = 0; i < 3; ++i) {
      out.normal[i][pending->index[j]] = vget_lane_s32(unit[i], 0);
      out.normal[i][pending->index[second]] = vget_lane_s32(unit[i], 1);
    }
  }
  pending->count = 0;
}

struct Job {
  const rig::Rig* rig;
  std::span<const fx::Mat34> palette;
  const SkinnedVertices* out;
  bool skip_dual;  // DQS vertices are the DQS pass's
  bool normals;
};

// One LBS vertex; false if its blended linear part would clamp (then nothing
// was written and the caller runs the scalar specification).
template <uint32_t K>
inline bool linear_vertex(const Job& job, uint32_t v, uint32_t index, PendingNormals* pending) {
  const rig::Rig& rig = *job.rig;
  const uint16_t* joints = rig.influence_palette.data() + size_t{v} * K;
  const fx::Unit* weights = rig.influence_weight.data() + size_t{v} * K;
  int64x2_t acc[6];
  for (int64x2_t& a : acc) a = vdupq_n_s64(0);
  for (uint32_t k = 0; k < K; ++k) {
    const EntryWords e = load_entry(job.palette[joints[k]]);
    const int32_t w = weights[k];
    for (int q = 0; q < 3; ++q) {
      acc[2 * q] = vmlal_n_s32(acc[2 * q], vget_low_s32(e.q[q]), w);
      acc[2 * q + 1] = vmlal_high_n_s32(acc[2 * q + 1], e.q[q], w);
    }
  }
  // Q2.30 x Q8.24 -> Q8.24 (linear) and Q2.30 x Q12.20 -> Q12.20 (translation).
  int64x2_t e[6];
  for (int i = 0; i < 6; ++i) e[i] = vrshrq_n_s64(acc[i], fx::kUnitFracBits);
  // Linear entries inside [-2^30, 2^30] (e + 2^30 <= 2^31 unsigned) are left
  // alone by the clamp; lane 1 of e[4] is t0, never out of range (limit 2^64 - 1).
  const uint64x2_t offset = vdupq_n_u64(uint64_t{1} << 30);
  const uint64x2_t limit = vdupq_n_u64(uint64_t{1} << 31);
  uint64x2_t outside = vcgtq_u64(vaddq_u64(vreinterpretq_u64_s64(e[0]), offset), limit);
  for (int i = 1; i < 4; ++i)
    outside = vorrq_u64(outside, vcgtq_u64(vaddq_u64(vreinterpretq_u64_s64(e[i]), offset), limit));
  const uint64x2_t offset_m22 = vsetq_lane_u64(0, offset, 1);
  const uint64x2_t limit_m22 = vsetq_lane_u64(~uint64_t{0}, limit, 1);
  outside = vorrq_u64(outside, vcgtq_u64(vaddq_u64(vreinterpretq_u64_s64(e[4]), offset_m22), limit_m22));
  if (vmaxvq_u32(vreinterpretq_u32_u64(outside)) != 0) return false;
  // In range: narrowing is exact.
  const int32x4_t lin_a = vcombine_s32(vmovn_s64(e[0]), vmovn_s64(e[1]));  // m00 m01 m02 m10
  const int32x4_t lin_b = vcombine_s32(vmovn_s64(e[2]), vmovn_s64(e[3]));  // m11 m12 m20 m21
  const int32x2_t lin_c = vmovn_s64(e[4]);                                 // m22, unused
  // Translation (Q12.20) times 2^24, as the scalar t * (1 << 24).
  const int64x2_t t01 = vshlq_n_s64(vextq_s64(e[4], e[5], 1), 24);
  const int64x2_t t2 = vshlq_n_s64(vextq_s64(e[5], e[5], 1), 24);
  const SkinnedVertices& out = *job.out;
  const Rows p = apply_linear(lin_a, lin_b, lin_c, rig.position[0][v], rig.position[1][v], rig.position[2][v]);
  const int32x2_t p01 = vqmovn_s64(vrshrq_n_s64(vaddq_s64(p.r01, t01), fx::kLinFracBits));
  const int32x2_t p2 = vqmovn_s64(vrshrq_n_s64(vaddq_s64(p.r2, t2), fx::kLinFracBits));
  out.position[0][index] = vget_lane_s32(p01, 0);
  out.position[1][index] = vget_lane_s32(p01, 1);
  out.position[2][index] = vget_lane_s32(p2, 0);
  if (job.normals) {
    const Rows n = apply_linear(lin_a, lin_b, lin_c, rig.normal[0][v], rig.normal[1][v], rig.normal[2][v]);
    const int32x2_t n01 = vqmovn_s64(vrshrq_n_s64(n.r01, fx::kLinFracBits));
    const int32x2_t n2 = vqmovn_s64(vrshrq_n_s64(n.r2, fx::kLinFracBits));
    const uint32_t slot = pending->count++;
    pending->c[0][slot] = vget_lane_s32(n01, 0);
    pending->c[1][slot] = vget_lane_s32(n01, 1);
    pending->c[2][slot] = vget_lane_s32(n2, 0);
    pending->index[slot] = index;
  }
  return true;
}

}  // namespace

uint32_t skin_linear_neon(const rig::Rig& rig, std::span<const fx::Mat34> palette, bool skip_dual, uint32_t first,
                          uint32_t count, const SkinnedVertices& out) {
  const Job job{&rig, palette, &out, skip_dual, !out.normal[0].empty() && !rig.normal[0].empty()};
  return dispatch_influences(
      rig.influences_per_vertex,
      [&]<uint32_t K>() { return run_lbs_blocks<&linear_vertex<K>, &finish_normals>(job, first, count); },
      [&] { return run_lbs_scalar(job, first, count); });
}

}  // namespace sinew::skin::detail
