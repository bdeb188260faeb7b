// AVX2 kernel of dual-quaternion skinning: the same output words as the
// scalar specification (skinning.cpp: skin_dual_vertex with
// fx::normalize_fast and fx::rot3_of_unit) for every input. Its functions are
// compiled for AVX2 (isa_region.hpp), on x86-64 only; called only when the
// CPU reports AVX2 (skinning.cpp).
//
// Four DQS vertices per step, one per 64-bit lane (a last group of fewer
// repeats its last vertex in the spare lanes and stores only the real ones):
//   - the K palette entries of the four vertices are loaded as 128-bit halves
//     and interleaved so that each lane holds two components in its two
//     32-bit halves; vpmuldq reads the low half (and the high half after a
//     32-bit shift), so every product is the scalar 32x32->64 product, and
//     every sum the scalar int64 sum (the scalar one never overflows on the
//     inputs it is defined for, so wrapping vector adds give its bits);
//   - the hemisphere test (antipodality, Kavan et al. 2008) is the plain dot,
//     exact because the palette is checked near unit once per call, as in the
//     scalar loop; a palette outside that range takes the scalar loop;
//   - fx::normalize_fast's rsqrt_fast runs four lanes at once (sim_core/fixed/avx2_lanes.hpp),
//     its divisions are per-lane variable round shifts;
//   - the scalar path narrows with sat_i32 at many steps; here every such
//     value that can leave int32 is checked to lie in it (where sat_i32 is the
//     identity), and a lane where any does not, whose squared norm takes
//     fx::normalize's division path (zero or above 2^63), whose negated
//     weight leaves int32, or whose |t| reaches 2^61 (the saturating position
//     adds could saturate) is redone by the scalar specification after its
//     group is stored. Posed unit palettes with convex weights never take it;
//     only the final position and normal narrowings saturate in the vector
//     path itself, exactly as sat_i32;
//   - the groups of a block go through the stages (blend, inverse norm, rest
//     of the normalisation, transform) together: each stage's loop body is
//     short enough for consecutive groups' dependency chains to overlap.
// K outside 1..8 takes the scalar loop.
#include <immintrin.h>

#include <cstring>

#include "sim_core/fixed/avx2_lanes.hpp"
#include "sim_core/fixed/isa_region.hpp"
#include "skinning_detail.hpp"

SINEW_ISA_BEGIN("avx2")

#include "dqs_blocks.hpp"

namespace sinew::skin::detail {
namespace {

using fx::avx2::round_shift_epi64;
using fx::avx2::sat_i32_epi64;

constexpr uint32_t kLanes = 4;

// Four quaternions, component c of quaternion l in the low 32 bits of lane l
// of the c-th vector (the high bits are not read: every use is a vpmuldq).
struct Quat4 {
  __m256i w, x, y, z;
};

inline __m256i load_halves(const fx::Quat& lo, const fx::Quat& hi) {
  __m128i a, b;
  static_assert(sizeof(fx::Quat) == sizeof(__m128i));
  std::memcpy(&a, &lo, sizeof(a));
  std::memcpy(&b, &hi, sizeof(b));
  return _mm256_inserti128_si256(_mm256_castsi128_si256(a), b, 1);
}

// Lane l holds (w, x) and (y, z) of q[l] after the 64-bit unpacks of
// [q0 | q2] and [q1 | q3].
inline Quat4 load_quat4(const fx::Quat& q0, const fx::Quat& q1, const fx::Quat& q2, const fx::Quat& q3) {
  const __m256i a = load_halves(q0, q2), b = load_halves(q1, q3);
  const __m256i wx = _mm256_unpacklo_epi64(a, b), yz = _mm256_unpackhi_epi64(a, b);
  return {wx, _mm256_srli_epi64(wx, 32), yz, _mm256_srli_epi64(yz, 32)};
}

inline __m256i mul(__m256i a, __m256i b) { return _mm256_mul_epi32(a, b); }
inline __m256i add(__m256i a, __m256i b) { return _mm256_add_epi64(a, b); }
inline __m256i sub(__m256i a, __m256i b) { return _mm256_sub_epi64(a, b); }

inline __m256i dot4(const Quat4& a, const Quat4& b) {
  return add(add(mul(a.w, b.w), mul(a.x, b.x)), add(mul(a.y, b.y), mul(a.z, b.z)));
}

inline __m256i load_lanes(const std::span<const int32_t>& column, const uint32_t v[kLanes], bool contiguous) {
  if (contiguous) return fx::avx2::load4_epi64(column.data() + v[0]);
  return _mm256_setr_epi64x(column[v[0]], column[v[1]], column[v[2]], column[v[3]]);
}

// Stores lanes [0, n) of int64 lanes holding int32 values at column[index[l]].
inline void store_lanes(std::span<int32_t> column, __m256i x, const uint32_t index[kLanes], uint32_t n,
                        bool contiguous) {
  if (contiguous) {
    const __m256i packed = _mm256_permutevar8x32_epi32(x, _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(column.data() + index[0]), _mm256_castsi256_si128(packed));
    return;
  }
  int64_t w[kLanes];
  fx::avx2::lanes(x, w);
  for (uint32_t l = 0; l < n; ++l) column[index[l]] = static_cast<int32_t>(w[l]);
}

// Range checks of one group: a lane goes back to the scalar specification if
// any value given to fits_i32 leaves int32, any value given to
// not_negative is negative, or any value given to below_2_61 is not.
// (A written constructor, not member initialisers: GCC compiles the implicit
// one outside the file's AVX2 region.)
struct Checks {
  Checks() : window(_mm256_setzero_si256()), sign(_mm256_setzero_si256()), wide(_mm256_setzero_si256()) {}
  __m256i window;  // OR of x + 2^31: below 2^32 iff every x fits int32
  __m256i sign;
  __m256i wide;  // OR of x + 2^61: below 2^62 iff every |x| < 2^61 (and -2^61)

  // x_plus is x + 2^31 for the x that must fit int32 (the caller folds the
  // 2^31 into an offset it subtracts anyway).
  void fits_i32_plus(__m256i x_plus) { window = _mm256_or_si256(window, x_plus); }
  void not_negative(__m256i x) { sign = _mm256_or_si256(sign, x); }
  void below_2_61(__m256i x) { wide = _mm256_or_si256(wide, add(x, _mm256_set1_epi64x(int64_t{1} << 61))); }
  uint32_t bad_lanes() const {
    // -(y >> k) is negative iff y >= 2^k.
    const __m256i zero = _mm256_setzero_si256();
    const __m256i bad = _mm256_or_si256(
        sign, _mm256_or_si256(sub(zero, _mm256_srli_epi64(window, 32)), sub(zero, _mm256_srli_epi64(wide, 62))));
    return static_cast<uint32_t>(_mm256_movemask_pd(_mm256_castsi256_pd(bad)));
  }
};

// round_shift(x, S) + 2^(63 - S): round_shift_epi64 without its last
// subtraction. For S <= 31 the offset is a multiple of 2^32, so the low 32
// bits (all vpmuldq reads) are round_shift(x, S)'s.
template <int S>
inline __m256i round_shift_low(__m256i x) {
  static_assert(S >= 1 && S <= 31);
  return _mm256_srli_epi64(add(x, _mm256_set1_epi64x(INT64_MIN + (int64_t{1} << (S - 1)))), S);
}
// The value x + 2^31 of x = round_shift_low<S>(...) - 2^(63 - S), for fits_i32_plus.
template <int S>
inline __m256i plus_2_31_of_low(__m256i low) {
  return sub(low, _mm256_set1_epi64x((int64_t{1} << (63 - S)) - (int64_t{1} << 31)));
}

// Up to four DQS vertices (n real, the spare lanes repeat the last) and their
// dual quaternion through the stages: blended (real Q30, dual Q20), then
// normalised. Components are kept with round_shift_low's offsets: only their
// low 32 bits are read.
struct Group {
  uint32_t v[kLanes];
  uint32_t n;
  Quat4 real, dual;
  fx::avx2::RsqrtX4 rsqrt;
  Checks checks;
};

// Stage 1: the blend and n30 of skin_dual_vertex.
template <uint32_t K>
inline void blend(const DualJob& job, Group* g) {
  const rig::Rig& rig = *job.rig;
  const fx::DualQuat* dual = job.dual.data();
  const uint16_t* joints[kLanes];
  const fx::Unit* weights[kLanes];
  for (uint32_t l = 0; l < kLanes; ++l) {
    joints[l] = rig.influence_palette.data() + size_t{g->v[l]} * K;
    weights[l] = rig.influence_weight.data() + size_t{g->v[l]} * K;
  }
  const fx::DualQuat* entry[K][kLanes];
  for (uint32_t k = 0; k < K; ++k)
    for (uint32_t l = 0; l < kLanes; ++l) entry[k][l] = dual + joints[l][k];
  const auto weight = [&](uint32_t k) {
    return _mm256_cvtepi32_epi64(_mm_setr_epi32(weights[0][k], weights[1][k], weights[2][k], weights[3][k]));
  };
  const auto real_of = [&](uint32_t k) {
    return load_quat4(entry[k][0]->real, entry[k][1]->real, entry[k][2]->real, entry[k][3]->real);
  };
  // Real parts first, with the hemisphere test (the first weight keeps its
  // sign: pivot . pivot >= 0), then the dual parts with the same weights:
  // two short loops keep their accumulators in registers.
  const __m256i zero = _mm256_setzero_si256();
  const __m256i weight_overflow = _mm256_set1_epi64x(int64_t{1} << 31);
  const Quat4 pivot = real_of(0);
  __m256i signed_weight[K];
  signed_weight[0] = weight(0);
  Quat4 real{mul(pivot.w, signed_weight[0]), mul(pivot.x, signed_weight[0]), mul(pivot.y, signed_weight[0]),
             mul(pivot.z, signed_weight[0])};
  __m256i bad_weight = zero;
#pragma GCC unroll 8
  for (uint32_t k = 1; k < K; ++k) {
    const Quat4 r = real_of(k);
    // Antipodality: the plain dot is exact for a near-unit palette (the
    // caller checked it); a negative one negates the weight. -INT32_MIN
    // leaves int32 (vpmuldq would read it back as INT32_MIN): such lanes go
    // to the scalar path.
    const __m256i negative = _mm256_cmpgt_epi64(zero, dot4(pivot, r));
    const __m256i w = sub(_mm256_xor_si256(weight(k), negative), negative);
    bad_weight = _mm256_or_si256(bad_weight, _mm256_cmpeq_epi64(w, weight_overflow));
    signed_weight[k] = w;
    real = {add(real.w, mul(r.w, w)), add(real.x, mul(r.x, w)), add(real.y, mul(r.y, w)), add(real.z, mul(r.z, w))};
  }
  Quat4 du{zero, zero, zero, zero};
#pragma GCC unroll 8
  for (uint32_t k = 0; k < K; ++k) {
    const Quat4 d = load_quat4(entry[k][0]->dual, entry[k][1]->dual, entry[k][2]->dual, entry[k][3]->dual);
    const __m256i w = signed_weight[k];
    du = {add(du.w, mul(d.w, w)), add(du.x, mul(d.x, w)), add(du.y, mul(d.y, w)), add(du.z, mul(d.z, w))};
  }
  g->checks.not_negative(bad_weight);  // all-ones (-1) where flagged
  // Q60 -> Q30 (real) and Q50 -> Q20 (dual): n30 of the scalar path, which
  // must not saturate here.
  const auto n30 = [&](__m256i x) {
    const __m256i low = round_shift_low<fx::kUnitFracBits>(x);
    g->checks.fits_i32_plus(plus_2_31_of_low<fx::kUnitFracBits>(low));
    return low;
  };
  g->real = {n30(real.w), n30(real.x), n30(real.y), n30(real.z)};
  g->dual = {n30(du.w), n30(du.x), n30(du.y), n30(du.z)};
}

// Stage 2: fx::normalize_fast's squared norm and reciprocal square root
// (a long dependency chain: a stage of its own).
inline void inverse_norm(Group* g) {
  const __m256i zero = _mm256_setzero_si256();
  // n2 as uint64 with wrapping adds, as the scalar one; n2 - 1 is negative
  // iff n2 == 0 or n2 > 2^63 (fx::normalize's division path).
  __m256i n2 = dot4(g->real, g->real);
  g->checks.not_negative(sub(n2, _mm256_set1_epi64x(1)));
  n2 = _mm256_or_si256(n2, _mm256_srli_epi64(_mm256_cmpeq_epi64(n2, zero), 63));  // any nonzero lane
  g->rsqrt = fx::avx2::rsqrt_fast_x4(n2);
}

// Stage 3: the rest of fx::normalize_fast.
inline void normalise(Group* g) {
  const fx::avx2::RsqrtX4& rs = g->rsqrt;
  // c * y round-shifted by rs.shift, plus the offset 2^(63 - shift) (a
  // multiple of 2^32 as shift <= 31): fx::avx2::VarRoundShift without its last
  // subtraction.
  const fx::avx2::VarRoundShift scale(rs.shift);
  const auto div = [&](__m256i c) { return _mm256_srlv_epi64(add(mul(c, rs.y), scale.bias), scale.shift); };
  // rq: |rq| < 2^30 + 8 (fx::normalize_fast), no saturation to check.
  const Quat4 rq{div(g->real.w), div(g->real.x), div(g->real.y), div(g->real.z)};
  const __m256i d_plus = sub(scale.offset, _mm256_set1_epi64x(int64_t{1} << 31));
  const auto div_dual = [&](__m256i c) {
    const __m256i low = div(c);
    g->checks.fits_i32_plus(sub(low, d_plus));
    return low;
  };
  const Quat4 d{div_dual(g->dual.w), div_dual(g->dual.x), div_dual(g->dual.y), div_dual(g->dual.z)};
  // rq . d is exact (|rq . d| < 2^63, see fx::normalize_fast).
  const __m256i k = round_shift_low<fx::kUnitFracBits>(dot4(rq, d));
  g->checks.fits_i32_plus(plus_2_31_of_low<fx::kUnitFracBits>(k));
  // d - mul_by_unit(k, rq): with the offsets, (d + off_d) - (m + 2^33); the
  // difference carries off_d - 2^33, still a multiple of 2^32.
  const __m256i diff_plus = sub(d_plus, _mm256_set1_epi64x(int64_t{1} << 33));
  const auto remove = [&](__m256i dc, __m256i rc) {
    const __m256i m = round_shift_low<fx::kUnitFracBits>(mul(k, rc));
    g->checks.fits_i32_plus(plus_2_31_of_low<fx::kUnitFracBits>(m));
    const __m256i diff = sub(dc, m);
    g->checks.fits_i32_plus(sub(diff, diff_plus));
    return diff;
  };
  g->real = rq;
  g->dual = {remove(d.w, rq.w), remove(d.x, rq.x), remove(d.y, rq.y), remove(d.z, rq.z)};
}

// An entry of rot3_of_unit from its Q60 double product (a function, not a
// lambda: GCC compiles lambdas outside the file's AVX2 region).
inline __m256i rot_entry(__m256i a) { return round_shift_low<fx::kUnitFracBits - 1>(a); }

// Stage 4: fx::rot3_of_unit, the translation, positions and normals; stores,
// then the scalar specification for the lanes a check flagged.
inline void transform(const DualJob& job, Group* g) {
  const Quat4& rq = g->real;
  const Quat4& d = g->dual;
  // e(2 a) = round_shift(a, 29) exactly, e(2^60 - 2 a) = round_shift(2^59 -
  // a, 29); every entry within 2^30 + 17 of zero (|rq| < 2^30 + 8).
  const __m256i xx = mul(rq.x, rq.x), yy = mul(rq.y, rq.y), zz = mul(rq.z, rq.z);
  const __m256i xy = mul(rq.x, rq.y), xz = mul(rq.x, rq.z), yz = mul(rq.y, rq.z);
  const __m256i wx = mul(rq.w, rq.x), wy = mul(rq.w, rq.y), wz = mul(rq.w, rq.z);
  const __m256i half_one = _mm256_set1_epi64x(int64_t{1} << 59);
  const __m256i rot[3][3] = {{rot_entry(sub(half_one, add(yy, zz))), rot_entry(sub(xy, wz)), rot_entry(add(xz, wy))},
                             {rot_entry(add(xy, wz)), rot_entry(sub(half_one, add(xx, zz))), rot_entry(sub(yz, wx))},
                             {rot_entry(sub(xz, wy)), rot_entry(add(yz, wx)), rot_entry(sub(half_one, add(xx, yy)))}};
  // t = w d_v - d_w r_v + r_v x d_v (Q50), exact (|t_c| < 2^62 + 2^35).
  const __m256i t[3] = {add(sub(mul(rq.w, d.x), mul(d.w, rq.x)), sub(mul(rq.y, d.z), mul(rq.z, d.y))),
                        add(sub(mul(rq.w, d.y), mul(d.w, rq.y)), sub(mul(rq.z, d.x), mul(rq.x, d.z))),
                        add(sub(mul(rq.w, d.z), mul(d.w, rq.z)), sub(mul(rq.x, d.y), mul(rq.y, d.x)))};
  // Rows of rot have norm below 2^30 + 64 and |p| < 2^31.8, so |R p| < 2^61.8;
  // with |t| < 2^61 neither saturating add of the scalar path saturates.
  for (int c = 0; c < 3; ++c) g->checks.below_2_61(t[c]);

  const rig::Rig& rig = *job.rig;
  const SkinnedVertices& out = *job.out;
  uint32_t index[kLanes];
  for (uint32_t l = 0; l < kLanes; ++l) index[l] = g->v[l] - job.first;
  const bool contiguous = g->n == kLanes && g->v[3] - g->v[0] == kLanes - 1;
  const __m256i p[3] = {load_lanes(rig.position[0], g->v, contiguous), load_lanes(rig.position[1], g->v, contiguous),
                        load_lanes(rig.position[2], g->v, contiguous)};
  for (int c = 0; c < 3; ++c) {
    const __m256i rp = add(add(mul(rot[c][0], p[0]), mul(rot[c][1], p[1])), mul(rot[c][2], p[2]));
    const __m256i position = sat_i32_epi64(round_shift_epi64<fx::kUnitFracBits>(add(add(rp, t[c]), t[c])));
    store_lanes(out.position[c], position, index, g->n, contiguous);
  }
  if (job.normals) {
    const __m256i nv[3] = {load_lanes(rig.normal[0], g->v, contiguous), load_lanes(rig.normal[1], g->v, contiguous),
                           load_lanes(rig.normal[2], g->v, contiguous)};
    for (int c = 0; c < 3; ++c) {
      const __m256i rn = add(add(mul(rot[c][0], nv[0]), mul(rot[c][1], nv[1])), mul(rot[c][2], nv[2]));
      store_lanes(out.normal[c], sat_i32_epi64(round_shift_epi64<fx::kUnitFracBits>(rn)), index, g->n, contiguous);
    }
  }
  uint32_t bad = g->checks.bad_lanes() & ((1u << g->n) - 1);
  while (bad != 0) {
    const uint32_t l = static_cast<uint32_t>(__builtin_ctz(bad));
    bad &= bad - 1;
    skin_dual_vertex(rig, job.dual, g->v[l], out, index[l], true);
  }
}

// The transform of a rigid run v .. v + 3 by a usable entry: positions and
// normals as transform() writes them (no add saturates, dqs_blocks.hpp).
inline void rigid_transform(const DualJob& job, const RigidEntry& e, uint32_t v) {
  const rig::Rig& rig = *job.rig;
  const SkinnedVertices& out = *job.out;
  const uint32_t index[kLanes] = {v - job.first, v + 1 - job.first, v + 2 - job.first, v + 3 - job.first};
  __m256i rot[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) rot[i][k] = _mm256_set1_epi32(e.rotation[i][k]);  // vpmuldq reads the low half
  const __m256i p[3] = {fx::avx2::load4_epi64(rig.position[0].data() + v),
                        fx::avx2::load4_epi64(rig.position[1].data() + v),
                        fx::avx2::load4_epi64(rig.position[2].data() + v)};
  for (int c = 0; c < 3; ++c) {
    const __m256i twice_t = _mm256_set1_epi64x(2 * e.t[c]);
    const __m256i rp = add(add(mul(rot[c][0], p[0]), mul(rot[c][1], p[1])), mul(rot[c][2], p[2]));
    store_lanes(out.position[c], sat_i32_epi64(round_shift_epi64<fx::kUnitFracBits>(add(rp, twice_t))), index, kLanes,
                true);
  }
  if (!job.normals) return;
  const __m256i n[3] = {fx::avx2::load4_epi64(rig.normal[0].data() + v),
                        fx::avx2::load4_epi64(rig.normal[1].data() + v),
                        fx::avx2::load4_epi64(rig.normal[2].data() + v)};
  for (int c = 0; c < 3; ++c) {
    const __m256i rn = add(add(mul(rot[c][0], n[0]), mul(rot[c][1], n[1])), mul(rot[c][2], n[2]));
    store_lanes(out.normal[c], sat_i32_epi64(round_shift_epi64<fx::kUnitFracBits>(rn)), index, kLanes, true);
  }
}

// Groups go through each stage together: a stage's loop body is short enough
// for the out-of-order core to overlap the long dependency chains (blend,
// rsqrt's Newton steps) of consecutive groups.
constexpr uint32_t kGroupsPerBlock = 8;

template <uint32_t K>
void run_block(const DualJob& job, Group* groups, uint32_t count) {
  for (uint32_t g = 0; g < count; ++g) blend<K>(job, &groups[g]);
  for (uint32_t g = 0; g < count; ++g) inverse_norm(&groups[g]);
  for (uint32_t g = 0; g < count; ++g) normalise(&groups[g]);
  for (uint32_t g = 0; g < count; ++g) transform(job, &groups[g]);
}

template <uint32_t K>
void run_dual(const DualJob& job, uint32_t count) {
  run_dual_groups<K, Group, kGroupsPerBlock, &run_block<K>, &rigid_transform>(job, count);
}

}  // namespace

void skin_dual_avx2(const rig::Rig& rig, std::span<const fx::DualQuat> dual, uint32_t first, uint32_t count,
                    const SkinnedVertices& out) {
  // The plain hemisphere dot needs a near-unit palette: checked once per call.
  if (!dual_palette_near_unit(dual)) return skin_dual_scalar(rig, dual, first, count, out);
  const DualJob job{&rig, dual, &out, first, !out.normal[0].empty() && !rig.normal[0].empty()};
  return dispatch_influences(
      rig.influences_per_vertex, [&]<uint32_t K>() { return run_dual<K>(job, count); },
      [&] { return skin_dual_scalar(rig, dual, first, count, out); });
}

}  // namespace sinew::skin::detail

SINEW_ISA_END
