// AVX-512 (F + VL + CD) kernel of dual-quaternion skinning: the same output
// words as the scalar specification (skinning.cpp: skin_dual_vertex with
// fx::normalize_fast and fx::rot3_of_unit) for every input. Its functions are
// compiled for those extensions (isa_region.hpp), on x86-64 only; called only
// when the CPU reports all three (skinning.cpp).
//
// The AVX2 kernel's method (skinning_dqs_avx2.cpp, whose comments give every
// bound) on eight DQS vertices per step, one per 64-bit lane, with the
// instructions AVX2 lacks:
//   - the hemisphere test negates a weight under a mask (vpsubq {k});
//   - fx::normalize_fast's rsqrt_fast counts leading zeros with vplzcntq
//     (sim_core/fixed/avx512_lanes.hpp);
//   - round half up of the final words is (x >> s) + ((x >> (s-1)) & 1) with
//     vpsraq, sat_i32 is vpmaxsq then vpminsq, and eight contiguous words
//     are narrowed (vpmovqd) and stored at once;
//   - the range checks that send a lane back to the specification are the
//     AVX2 kernel's, read out as a lane mask.
//   - a group of eight consecutive vertices (the common case) reads its
//     weights as one block and its palette indices from one base, loads and
//     stores its positions and normals whole; each palette entry's real and
//     dual parts are loaded together.
// Rigid runs (dqs_blocks.hpp) are eight consecutive vertices of one palette
// entry. K outside 1..8 takes the scalar loop.

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

#include "dqs_blocks.hpp"

namespace sinew::skin::detail {
namespace {

using fx::avx512::round_shift_epi64;
using fx::avx512::sat_i32_epi64;

constexpr uint32_t kLanes = 8;

// Eight quaternions, component c of quaternion l in the low 32 bits of lane
// l of the c-th vector (the high bits are not read: every use is a vpmuldq).
struct Quat8 {
  __m512i w, x, y, z;
};

inline __m128i load_quat(const fx::Quat& q) {
  static_assert(sizeof(fx::Quat) == sizeof(__m128i));
  __m128i a;
  std::memcpy(&a, &q, sizeof(a));
  return a;
}

// [a | b | c | d], one quaternion per 128-bit lane.
inline __m512i load_quarters(const fx::Quat& a, const fx::Quat& b, const fx::Quat& c, const fx::Quat& d) {
  const __m256i lo = _mm256_inserti128_si256(_mm256_castsi128_si256(load_quat(a)), load_quat(b), 1);
  const __m256i hi = _mm256_inserti128_si256(_mm256_castsi128_si256(load_quat(c)), load_quat(d), 1);
  return _mm512_inserti64x4(_mm512_castsi256_si512(lo), hi, 1);
}

// Lane l holds (w, x) and (y, z) of q[l] after the 64-bit unpacks of
// [q0 | q2 | q4 | q6] and [q1 | q3 | q5 | q7].
inline Quat8 load_quat8(const fx::Quat* const q[kLanes]) {
  const __m512i a = load_quarters(*q[0], *q[2], *q[4], *q[6]), b = load_quarters(*q[1], *q[3], *q[5], *q[7]);
  const __m512i wx = _mm512_unpacklo_epi64(a, b), yz = _mm512_unpackhi_epi64(a, b);
  return {wx, _mm512_srli_epi64(wx, 32), yz, _mm512_srli_epi64(yz, 32)};
}

inline __m512i mul(__m512i a, __m512i b) { return _mm512_mul_epi32(a, b); }
inline __m512i add(__m512i a, __m512i b) { return _mm512_add_epi64(a, b); }
inline __m512i sub(__m512i a, __m512i b) { return _mm512_sub_epi64(a, b); }
inline __m512i set1(int64_t x) { return _mm512_set1_epi64(x); }

inline __m512i dot4(const Quat8& a, const Quat8& b) {
  return add(add(mul(a.w, b.w), mul(a.x, b.x)), add(mul(a.y, b.y), mul(a.z, b.z)));
}

inline __m512i load8_epi64(const int32_t* p) {
  return _mm512_cvtepi32_epi64(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)));
}

inline __m512i load_lanes(const std::span<const int32_t>& column, const uint32_t v[kLanes], bool contiguous) {
  if (contiguous) return load8_epi64(column.data() + v[0]);
  return _mm512_setr_epi64(column[v[0]], column[v[1]], column[v[2]], column[v[3]], column[v[4]], column[v[5]],
                           column[v[6]], column[v[7]]);
}

// Stores lanes [0, n) of int64 lanes holding int32 values at column[index[l]].
inline void store_lanes(std::span<int32_t> column, __m512i x, const uint32_t index[kLanes], uint32_t n,
                        bool contiguous) {
  const __m256i words = _mm512_cvtepi64_epi32(x);
  if (contiguous) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(column.data() + index[0]), words);
    return;
  }
  int32_t w[kLanes];
  std::memcpy(w, &words, sizeof(w));
  for (uint32_t l = 0; l < n; ++l) column[index[l]] = w[l];
}

// Range checks of one group, as the AVX2 kernel's: a lane goes back to the
// scalar specification if any value given to fits_i32 leaves int32, any
// value given to not_negative is negative, or any value given to below_2_61
// is not. (A written constructor: GCC compiles implicit ones outside the
// file's ISA region.)
struct Checks {
  Checks() : window(_mm512_setzero_si512()), sign(_mm512_setzero_si512()), wide(_mm512_setzero_si512()) {}
  __m512i window;  // OR of x + 2^31: below 2^32 iff every x fits int32
  __m512i sign;
  __m512i wide;  // OR of x + 2^61: below 2^62 iff every |x| < 2^61 (and -2^61)

  void fits_i32_plus(__m512i x_plus) { window = _mm512_or_si512(window, x_plus); }
  void not_negative(__m512i x) { sign = _mm512_or_si512(sign, x); }
  void below_2_61(__m512i x) { wide = _mm512_or_si512(wide, add(x, set1(int64_t{1} << 61))); }
  uint32_t bad_lanes() const {
    const __m512i zero = _mm512_setzero_si512();
    return static_cast<uint32_t>(_mm512_cmplt_epi64_mask(sign, zero) |
                                 _mm512_cmpge_epu64_mask(window, set1(int64_t{1} << 32)) |
                                 _mm512_cmpge_epu64_mask(wide, set1(int64_t{1} << 62)));
  }
};

// round_shift(x, S) + 2^(63 - S), as the AVX2 kernel's round_shift_low: for
// S <= 31 the offset is a multiple of 2^32, so the low 32 bits (all vpmuldq
// reads) are round_shift(x, S)'s.
template <int S>
inline __m512i round_shift_low(__m512i x) {
  static_assert(S >= 1 && S <= 31);
  return _mm512_srli_epi64(add(x, set1(INT64_MIN + (int64_t{1} << (S - 1)))), S);
}
// The value x + 2^31 of x = round_shift_low<S>(...) - 2^(63 - S), for fits_i32_plus.
template <int S>
inline __m512i plus_2_31_of_low(__m512i low) {
  return sub(low, set1((int64_t{1} << (63 - S)) - (int64_t{1} << 31)));
}

// round_shift by a per-lane shift in [0, 31] with the offset 2^(63 - shift)
// kept (fx::avx2::VarRoundShift's form, eight lanes).
struct VarRoundShift8 {
  __m512i shift, bias, offset;
  explicit VarRoundShift8(__m512i s)
      : shift(s),
        bias(add(_mm512_srli_epi64(_mm512_sllv_epi64(set1(1), s), 1), set1(INT64_MIN))),
        offset(_mm512_srlv_epi64(set1(INT64_MIN), s)) {}
};

// Up to eight DQS vertices (n real, the spare lanes repeat the last) and
// their dual quaternion through the stages.
struct Group {
  uint32_t v[kLanes];
  uint32_t n;
  Quat8 real, dual;
  fx::avx512::RsqrtX8 rsqrt;
  Checks checks;
};

inline bool in_a_row(const Group& g) { return g.n == kLanes && g.v[kLanes - 1] - g.v[0] == kLanes - 1; }

// The weights of influence k of a group, sign-extended per lane. A group of
// eight consecutive vertices with K <= 4 reads its 8 K weights as one block
// (two masked loads, then one two-source permute per influence); any other
// group reads them per lane.
template <uint32_t K, bool InARow>
struct GroupWeights;

template <uint32_t K>
struct GroupWeights<K, true> {
  static_assert(K <= 4);
  static constexpr uint32_t kWords = 8 * K;
  __m512i low, high;  // words 0..15 and 16..31 of the block, zero past 8 K
  GroupWeights(const rig::Rig& rig, const Group& g) {
    const fx::Unit* block = rig.influence_weight.data() + size_t{g.v[0]} * K;
    // Masked: nothing past the block is read.
    low = _mm512_maskz_loadu_epi32(static_cast<__mmask16>(kWords >= 16 ? 0xFFFFu : (1u << kWords) - 1), block);
    high = _mm512_maskz_loadu_epi32(static_cast<__mmask16>(kWords > 16 ? (1u << (kWords - 16)) - 1 : 0u),
                                    block + (kWords > 16 ? 16 : 0));
  }
  __m512i operator()(uint32_t k) const {
    // Lane l takes word k + K l (indices 16..31 select `high`).
    const auto at = [k](uint32_t l) { return static_cast<int32_t>(k + K * l); };
    const __m512i index =
        _mm512_setr_epi32(at(0), at(1), at(2), at(3), at(4), at(5), at(6), at(7), 0, 0, 0, 0, 0, 0, 0, 0);
    return _mm512_cvtepi32_epi64(_mm512_castsi512_si256(_mm512_permutex2var_epi32(low, index, high)));
  }
};

template <uint32_t K>
struct GroupWeights<K, false> {
  const fx::Unit* lane[kLanes];
  GroupWeights(const rig::Rig& rig, const Group& g) {
    for (uint32_t l = 0; l < kLanes; ++l) lane[l] = rig.influence_weight.data() + size_t{g.v[l]} * K;
  }
  __m512i operator()(uint32_t k) const {
    return _mm512_cvtepi32_epi64(_mm256_setr_epi32(lane[0][k], lane[1][k], lane[2][k], lane[3][k], lane[4][k],
                                                   lane[5][k], lane[6][k], lane[7][k]));
  }
};

// Influence k's eight palette entries: their real and dual parts are read
// together, so each entry's address is made once and the blend keeps no
// table of them. InARow: palette indices of consecutive vertices from one
// base.
template <uint32_t K, bool InARow>
inline void load_entries(const rig::Rig& rig, const fx::DualQuat* dual, const Group& g, uint32_t k, Quat8* real,
                         Quat8* dual_part) {
  const fx::Quat* r[kLanes];
  const fx::Quat* d[kLanes];
  for (uint32_t l = 0; l < kLanes; ++l) {
    const size_t at = InARow ? size_t{g.v[0]} * K + l * K + k : size_t{g.v[l]} * K + k;
    const fx::DualQuat& e = dual[rig.influence_palette[at]];
    r[l] = &e.real;
    d[l] = &e.dual;
  }
  *real = load_quat8(r);
  *dual_part = load_quat8(d);
}

// Stage 1: the blend and n30 of skin_dual_vertex. InARow: the group is
// eight consecutive vertices (in_a_row).
template <uint32_t K, bool InARow>
inline void blend(const DualJob& job, Group* g) {
  const rig::Rig& rig = *job.rig;
  const fx::DualQuat* dual = job.dual.data();
  const GroupWeights<K, InARow && K <= 4> weight(rig, *g);
  // The hemisphere test against the first entry (whose weight keeps its
  // sign); real and dual parts take the same signed weight. The int64 sums
  // wrap, so their order is free: the words are the scalar sums'.
  const __m512i zero = _mm512_setzero_si512();
  const __m512i weight_overflow = set1(int64_t{1} << 31);
  Quat8 pivot, d;
  load_entries<K, InARow>(rig, dual, *g, 0, &pivot, &d);
  const __m512i w0 = weight(0);
  Quat8 real{mul(pivot.w, w0), mul(pivot.x, w0), mul(pivot.y, w0), mul(pivot.z, w0)};
  Quat8 du{mul(d.w, w0), mul(d.x, w0), mul(d.y, w0), mul(d.z, w0)};
  __mmask8 bad_weight = 0;
#pragma GCC unroll 8
  for (uint32_t k = 1; k < K; ++k) {
    Quat8 r;
    load_entries<K, InARow>(rig, dual, *g, k, &r, &d);
    // Antipodality: a negative plain dot negates the weight; -INT32_MIN
    // leaves int32, such lanes go to the scalar path.
    const __m512i wk = weight(k);
    const __m512i w = _mm512_mask_sub_epi64(wk, _mm512_cmplt_epi64_mask(dot4(pivot, r), zero), zero, wk);
    bad_weight = static_cast<__mmask8>(bad_weight | _mm512_cmpeq_epi64_mask(w, weight_overflow));
    real = {add(real.w, mul(r.w, w)), add(real.x, mul(r.x, w)), add(real.y, mul(r.y, w)), add(real.z, mul(r.z, w))};
    du = {add(du.w, mul(d.w, w)), add(du.x, mul(d.x, w)), add(du.y, mul(d.y, w)), add(du.z, mul(d.z, w))};
  }
  g->checks.not_negative(_mm512_maskz_mov_epi64(bad_weight, set1(-1)));
  // Q60 -> Q30 (real) and Q50 -> Q20 (dual): n30 of the scalar path, which
  // must not saturate here.
  const auto n30 = [&](__m512i x) {
    const __m512i low = round_shift_low<fx::kUnitFracBits>(x);
    g->checks.fits_i32_plus(plus_2_31_of_low<fx::kUnitFracBits>(low));
    return low;
  };
  g->real = {n30(real.w), n30(real.x), n30(real.y), n30(real.z)};
  g->dual = {n30(du.w), n30(du.x), n30(du.y), n30(du.z)};
}

// Stage 2: fx::normalize_fast's squared norm and reciprocal square root.
inline void inverse_norm(Group* g) {
  // n2 as uint64 with wrapping adds, as the scalar one; n2 - 1 is negative
  // iff n2 == 0 or n2 > 2^63 (fx::normalize's division path).
  __m512i n2 = dot4(g->real, g->real);
  g->checks.not_negative(sub(n2, set1(1)));
  n2 = _mm512_mask_mov_epi64(n2, _mm512_testn_epi64_mask(n2, n2), set1(1));  // any nonzero lane
  g->rsqrt = fx::avx512::rsqrt_fast_x8(n2);
}

// Stage 3: the rest of fx::normalize_fast.
inline void normalise(Group* g) {
  const fx::avx512::RsqrtX8& rs = g->rsqrt;
  const VarRoundShift8 scale(rs.shift);
  const auto div = [&](__m512i c) { return _mm512_srlv_epi64(add(mul(c, rs.y), scale.bias), scale.shift); };
  // rq: |rq| < 2^30 + 8 (fx::normalize_fast), no saturation to check.
  const Quat8 rq{div(g->real.w), div(g->real.x), div(g->real.y), div(g->real.z)};
  const __m512i d_plus = sub(scale.offset, set1(int64_t{1} << 31));
  const auto div_dual = [&](__m512i c) {
    const __m512i low = div(c);
    g->checks.fits_i32_plus(sub(low, d_plus));
    return low;
  };
  const Quat8 d{div_dual(g->dual.w), div_dual(g->dual.x), div_dual(g->dual.y), div_dual(g->dual.z)};
  const __m512i k = round_shift_low<fx::kUnitFracBits>(dot4(rq, d));
  g->checks.fits_i32_plus(plus_2_31_of_low<fx::kUnitFracBits>(k));
  const __m512i diff_plus = sub(d_plus, set1(int64_t{1} << 33));
  const auto remove = [&](__m512i dc, __m512i rc) {
    const __m512i m = round_shift_low<fx::kUnitFracBits>(mul(k, rc));
    g->checks.fits_i32_plus(plus_2_31_of_low<fx::kUnitFracBits>(m));
    const __m512i diff = sub(dc, m);
    g->checks.fits_i32_plus(sub(diff, diff_plus));
    return diff;
  };
  g->real = rq;
  g->dual = {remove(d.w, rq.w), remove(d.x, rq.x), remove(d.y, rq.y), remove(d.z, rq.z)};
}

// An entry of rot3_of_unit from its Q60 double product (a function, not a
// lambda: GCC compiles lambdas outside the file's ISA region).
inline __m512i rot_entry(__m512i a) { return round_shift_low<fx::kUnitFracBits - 1>(a); }

// Stage 4: fx::rot3_of_unit, the translation, positions and normals; stores,
// then the scalar specification for the lanes a check flagged.
// InARow: the group is eight consecutive vertices (in_a_row), loaded and
// stored whole.
template <bool InARow>
inline void transform(const DualJob& job, Group* g) {
  const Quat8& rq = g->real;
  const Quat8& d = g->dual;
  const __m512i xx = mul(rq.x, rq.x), yy = mul(rq.y, rq.y), zz = mul(rq.z, rq.z);
  const __m512i xy = mul(rq.x, rq.y), xz = mul(rq.x, rq.z), yz = mul(rq.y, rq.z);
  const __m512i wx = mul(rq.w, rq.x), wy = mul(rq.w, rq.y), wz = mul(rq.w, rq.z);
  const __m512i half_one = set1(int64_t{1} << 59);
  const __m512i rot[3][3] = {{rot_entry(sub(half_one, add(yy, zz))), rot_entry(sub(xy, wz)), rot_entry(add(xz, wy))},
                             {rot_entry(add(xy, wz)), rot_entry(sub(half_one, add(xx, zz))), rot_entry(sub(yz, wx))},
                             {rot_entry(sub(xz, wy)), rot_entry(add(yz, wx)), rot_entry(sub(half_one, add(xx, yy)))}};
  // t = w d_v - d_w r_v + r_v x d_v (Q50), exact.
  const __m512i t[3] = {add(sub(mul(rq.w, d.x), mul(d.w, rq.x)), sub(mul(rq.y, d.z), mul(rq.z, d.y))),
                        add(sub(mul(rq.w, d.y), mul(d.w, rq.y)), sub(mul(rq.z, d.x), mul(rq.x, d.z))),
                        add(sub(mul(rq.w, d.z), mul(d.w, rq.z)), sub(mul(rq.x, d.y), mul(rq.y, d.x)))};
  for (int c = 0; c < 3; ++c) g->checks.below_2_61(t[c]);

  const rig::Rig& rig = *job.rig;
  const SkinnedVertices& out = *job.out;
  uint32_t index[kLanes];
  for (uint32_t l = 0; l < kLanes; ++l) index[l] = g->v[l] - job.first;
  constexpr bool contiguous = InARow;
  const __m512i p[3] = {load_lanes(rig.position[0], g->v, contiguous), load_lanes(rig.position[1], g->v, contiguous),
                        load_lanes(rig.position[2], g->v, contiguous)};
  for (int c = 0; c < 3; ++c) {
    const __m512i rp = add(add(mul(rot[c][0], p[0]), mul(rot[c][1], p[1])), mul(rot[c][2], p[2]));
    const __m512i position = sat_i32_epi64(round_shift_epi64<fx::kUnitFracBits>(add(add(rp, t[c]), t[c])));
    store_lanes(out.position[c], position, index, g->n, contiguous);
  }
  if (job.normals) {
    const __m512i nv[3] = {load_lanes(rig.normal[0], g->v, contiguous), load_lanes(rig.normal[1], g->v, contiguous),
                           load_lanes(rig.normal[2], g->v, contiguous)};
    for (int c = 0; c < 3; ++c) {
      const __m512i rn = add(add(mul(rot[c][0], nv[0]), mul(rot[c][1], nv[1])), mul(rot[c][2], nv[2]));
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

// The transform of a rigid run v .. v + 7 by a usable entry (dqs_blocks.hpp):
// positions and normals as transform() writes them (no add saturates).
inline void rigid_transform(const DualJob& job, const RigidEntry& e, uint32_t v) {
  const rig::Rig& rig = *job.rig;
  const SkinnedVertices& out = *job.out;
  uint32_t index[kLanes];
  for (uint32_t l = 0; l < kLanes; ++l) index[l] = v + l - job.first;
  __m512i rot[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) rot[i][k] = _mm512_set1_epi32(e.rotation[i][k]);  // vpmuldq reads the low half
  const __m512i p[3] = {load8_epi64(rig.position[0].data() + v), load8_epi64(rig.position[1].data() + v),
                        load8_epi64(rig.position[2].data() + v)};
  for (int c = 0; c < 3; ++c) {
    const __m512i twice_t = set1(2 * e.t[c]);
    const __m512i rp = add(add(mul(rot[c][0], p[0]), mul(rot[c][1], p[1])), mul(rot[c][2], p[2]));
    store_lanes(out.position[c], sat_i32_epi64(round_shift_epi64<fx::kUnitFracBits>(add(rp, twice_t))), index, kLanes,
                true);
  }
  if (!job.normals) return;
  const __m512i n[3] = {load8_epi64(rig.normal[0].data() + v), load8_epi64(rig.normal[1].data() + v),
                        load8_epi64(rig.normal[2].data() + v)};
  for (int c = 0; c < 3; ++c) {
    const __m512i rn = add(add(mul(rot[c][0], n[0]), mul(rot[c][1], n[1])), mul(rot[c][2], n[2]));
    store_lanes(out.normal[c], sat_i32_epi64(round_shift_epi64<fx::kUnitFracBits>(rn)), index, kLanes, true);
  }
}

// Groups go through each stage together, so that consecutive groups' long
// dependency chains overlap.
constexpr uint32_t kGroupsPerBlock = 4;

template <uint32_t K>
void run_block(const DualJob& job, Group* groups, uint32_t count) {
  for (uint32_t g = 0; g < count; ++g)
    in_a_row(groups[g]) ? blend<K, true>(job, &groups[g]) : blend<K, false>(job, &groups[g]);
  for (uint32_t g = 0; g < count; ++g) inverse_norm(&groups[g]);
  for (uint32_t g = 0; g < count; ++g) normalise(&groups[g]);
  for (uint32_t g = 0; g < count; ++g)
    in_a_row(groups[g]) ? transform<true>(job, &groups[g]) : transform<false>(job, &groups[g]);
}

template <uint32_t K>
void run_dual(const DualJob& job, uint32_t count) {
  run_dual_groups<K, Group, kGroupsPerBlock, &run_block<K>, &rigid_transform>(job, count);
}

}  // namespace

void skin_dual_avx512(const rig::Rig& rig, std::span<const fx::DualQuat> dual, uint32_t first, uint32_t count,
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
