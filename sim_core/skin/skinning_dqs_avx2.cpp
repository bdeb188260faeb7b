// AVX2 kernel of dual-quaternion skinning: the same output words as the
// scalar specification (skinning.cpp: skin_dual_vertex with
// fx::normalize_fast and fx::rot3_of_unit) for every input. Built with -mavx2
// for this file only, and only on x86-64; called only when the CPU reports
// AVX2 (skinning.cpp).
//
// Four DQS vertices per step, one per 64-bit lane (a last group of fewer
// repeats its last vertex in the spare lanes and stores only the real ones):
//   - the K palette entries of the four vertices are loaded as 128-bit halves
//     and interleaved so that each lane holds two components in its two
//     32-bit halves; vpmuldq reads the low half (and the high half after a
//     32-bit shift), so every product is the scalar 32x32->64 product, and
//     every sum the scalar int64 sum (the scalar one never overflows on the
//     inputs it is defined for, so wrapping vector adds give its bits);
//   - the hemisphere test (Kavan et al. 2008, section 4.2) is the plain dot,
//     exact because the palette is checked near unit once per call, as in the
//     scalar loop; a palette outside that range takes the scalar loop;
//   - fx::normalize_fast's rsqrt_fast runs four lanes at once (avx2_lanes.hpp),
//     its divisions are per-lane variable round shifts;
//   - the scalar path narrows with sat_i32 at many steps; here every such
//     value is checked to lie in int32 (where sat_i32 is the identity), and a
//     lane where any does not, whose squared norm takes fx::normalize's
//     division path (zero or above 2^63), whose negated weight leaves int32,
//     or whose position sum saturates in int64, is redone by the scalar
//     specification after the group is stored. Real rigs (unit palettes,
//     convex weights) never take it; only the final position and normal
//     narrowings saturate in the vector path itself, exactly as sat_i32.
// K outside 1..8 takes the scalar loop.
#include <immintrin.h>

#include <cstring>

#include "avx2_lanes.hpp"
#include "skinning_detail.hpp"

namespace sinew::skin::detail {
namespace {

using avx2::round_shift_epi64;
using avx2::sat_i32_epi64;

constexpr uint32_t kLanes = 4;

struct DualJob {
  const rig::Rig* rig;
  std::span<const fx::DualQuat> dual;
  const SkinnedVertices* out;
  uint32_t first;
  bool normals;
};

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
  if (contiguous) return avx2::load4_epi64(column.data() + v[0]);
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
  avx2::lanes(x, w);
  for (uint32_t l = 0; l < n; ++l) column[index[l]] = static_cast<int32_t>(w[l]);
}

// Range checks of one group: a lane goes back to the scalar specification if
// any value added to `window` leaves int32 or any value added to `sign` is
// negative.
struct Checks {
  __m256i window = _mm256_setzero_si256();  // OR of (x - INT32_MIN): below 2^32 iff every x fits int32
  __m256i sign = _mm256_setzero_si256();

  __m256i fits_i32(__m256i x) {
    window = _mm256_or_si256(window, sub(x, _mm256_set1_epi64x(INT32_MIN)));
    return x;
  }
  // Flags lanes where s = a + b wrapped (a and b of one sign, s of the other).
  void no_overflow(__m256i s, __m256i a, __m256i b) {
    sign = _mm256_or_si256(sign, _mm256_and_si256(_mm256_xor_si256(s, a), _mm256_xor_si256(s, b)));
  }
  uint32_t bad_lanes() const {
    // -(window >> 32) is negative iff window >= 2^32.
    const __m256i wide = sub(_mm256_setzero_si256(), _mm256_srli_epi64(window, 32));
    return static_cast<uint32_t>(_mm256_movemask_pd(_mm256_castsi256_pd(_mm256_or_si256(sign, wide))));
  }
};

// skin_dual_vertex for the vertices v[0..4) (n of them real), written at
// v[l] - first.
template <uint32_t K>
void dual_group(const DualJob& job, const uint32_t v[kLanes], uint32_t n) {
  const rig::Rig& rig = *job.rig;
  const fx::DualQuat* dual = job.dual.data();
  const uint16_t* joints[kLanes];
  const fx::Unit* weights[kLanes];
  for (uint32_t l = 0; l < kLanes; ++l) {
    joints[l] = rig.influence_palette.data() + size_t{v[l]} * K;
    weights[l] = rig.influence_weight.data() + size_t{v[l]} * K;
  }
  Checks checks;
  const __m256i zero = _mm256_setzero_si256();
  const __m256i weight_overflow = _mm256_set1_epi64x(int64_t{1} << 31);
  Quat4 pivot{}, real{zero, zero, zero, zero}, du{zero, zero, zero, zero};
  for (uint32_t k = 0; k < K; ++k) {
    const fx::DualQuat& e0 = dual[joints[0][k]];
    const fx::DualQuat& e1 = dual[joints[1][k]];
    const fx::DualQuat& e2 = dual[joints[2][k]];
    const fx::DualQuat& e3 = dual[joints[3][k]];
    const Quat4 r = load_quat4(e0.real, e1.real, e2.real, e3.real);
    const Quat4 d = load_quat4(e0.dual, e1.dual, e2.dual, e3.dual);
    __m256i w = _mm256_cvtepi32_epi64(_mm_setr_epi32(weights[0][k], weights[1][k], weights[2][k], weights[3][k]));
    if (k == 0) {
      pivot = r;  // pivot . pivot >= 0: the first weight keeps its sign
    } else {
      // Antipodality: the plain dot is exact for a near-unit palette (the
      // caller checked it); a negative one negates the weight. -INT32_MIN
      // leaves int32 (vpmuldq would read it back as INT32_MIN): such lanes
      // go to the scalar path.
      const __m256i negative = _mm256_cmpgt_epi64(zero, dot4(pivot, r));
      w = sub(_mm256_xor_si256(w, negative), negative);
      checks.sign = _mm256_or_si256(checks.sign, _mm256_cmpeq_epi64(w, weight_overflow));
    }
    real = {add(real.w, mul(r.w, w)), add(real.x, mul(r.x, w)), add(real.y, mul(r.y, w)), add(real.z, mul(r.z, w))};
    du = {add(du.w, mul(d.w, w)), add(du.x, mul(d.x, w)), add(du.y, mul(d.y, w)), add(du.z, mul(d.z, w))};
  }
  // Q60 -> Q30 (real) and Q50 -> Q20 (dual): n30 of the scalar path.
  const auto n30 = [&](__m256i x) { return checks.fits_i32(round_shift_epi64<fx::kUnitFracBits>(x)); };
  const Quat4 b_real{n30(real.w), n30(real.x), n30(real.y), n30(real.z)};
  const Quat4 b_dual{n30(du.w), n30(du.x), n30(du.y), n30(du.z)};

  // fx::normalize_fast. n2 as uint64 with wrapping adds, as the scalar one;
  // n2 - 1 is negative iff n2 == 0 or n2 > 2^63 (fx::normalize's path).
  __m256i n2 = dot4(b_real, b_real);
  checks.sign = _mm256_or_si256(checks.sign, sub(n2, _mm256_set1_epi64x(1)));
  n2 = _mm256_or_si256(n2, _mm256_srli_epi64(_mm256_cmpeq_epi64(n2, zero), 63));  // any nonzero lane
  const avx2::RsqrtX4 rs = avx2::rsqrt_fast_x4(n2);
  const avx2::VarRoundShift scale(rs.shift);
  const auto div = [&](__m256i c) { return checks.fits_i32(scale(mul(c, rs.y))); };
  const Quat4 rq{div(b_real.w), div(b_real.x), div(b_real.y), div(b_real.z)};
  Quat4 d{div(b_dual.w), div(b_dual.x), div(b_dual.y), div(b_dual.z)};
  // rq . d is exact (|rq . d| < 2^63, see fx::normalize_fast).
  const __m256i k = checks.fits_i32(round_shift_epi64<fx::kUnitFracBits>(dot4(rq, d)));
  const auto remove = [&](__m256i dc, __m256i rc) {
    const __m256i m = checks.fits_i32(round_shift_epi64<fx::kUnitFracBits>(mul(k, rc)));  // mul_by_unit
    return checks.fits_i32(sub(dc, m));                                                   // sub_sat
  };
  d = {remove(d.w, rq.w), remove(d.x, rq.x), remove(d.y, rq.y), remove(d.z, rq.z)};

  // fx::rot3_of_unit: e(2 a) = round_shift(a, 29) exactly, and
  // e(2^60 - 2 a) = round_shift(2^59 - a, 29).
  const __m256i xx = mul(rq.x, rq.x), yy = mul(rq.y, rq.y), zz = mul(rq.z, rq.z);
  const __m256i xy = mul(rq.x, rq.y), xz = mul(rq.x, rq.z), yz = mul(rq.y, rq.z);
  const __m256i wx = mul(rq.w, rq.x), wy = mul(rq.w, rq.y), wz = mul(rq.w, rq.z);
  const __m256i half_one = _mm256_set1_epi64x(int64_t{1} << 59);
  const auto e = [&](__m256i a) { return checks.fits_i32(round_shift_epi64<fx::kUnitFracBits - 1>(a)); };
  const __m256i rot[3][3] = {{e(sub(half_one, add(yy, zz))), e(sub(xy, wz)), e(add(xz, wy))},
                             {e(add(xy, wz)), e(sub(half_one, add(xx, zz))), e(sub(yz, wx))},
                             {e(sub(xz, wy)), e(add(yz, wx)), e(sub(half_one, add(xx, yy)))}};
  // t = w d_v - d_w r_v + r_v x d_v (Q50), exact (|t_c| < 2^62 + 2^35).
  const __m256i t[3] = {add(sub(mul(rq.w, d.x), mul(d.w, rq.x)), sub(mul(rq.y, d.z), mul(rq.z, d.y))),
                        add(sub(mul(rq.w, d.y), mul(d.w, rq.y)), sub(mul(rq.z, d.x), mul(rq.x, d.z))),
                        add(sub(mul(rq.w, d.z), mul(d.w, rq.z)), sub(mul(rq.x, d.y), mul(rq.y, d.x)))};

  const SkinnedVertices& out = *job.out;
  uint32_t index[kLanes];
  for (uint32_t l = 0; l < kLanes; ++l) index[l] = v[l] - job.first;
  const bool contiguous = n == kLanes && v[3] - v[0] == kLanes - 1;
  const __m256i p[3] = {load_lanes(rig.position[0], v, contiguous), load_lanes(rig.position[1], v, contiguous),
                        load_lanes(rig.position[2], v, contiguous)};
  __m256i position[3];
  for (int c = 0; c < 3; ++c) {
    const __m256i rp = add(add(mul(rot[c][0], p[0]), mul(rot[c][1], p[1])), mul(rot[c][2], p[2]));
    // add_sat_i64(add_sat_i64(rp, t), t): a lane where either sum wraps is
    // redone by the scalar path (which saturates it).
    const __m256i s1 = add(rp, t[c]);
    checks.no_overflow(s1, rp, t[c]);
    const __m256i s2 = add(s1, t[c]);
    checks.no_overflow(s2, s1, t[c]);
    position[c] = sat_i32_epi64(round_shift_epi64<fx::kUnitFracBits>(s2));
  }
  __m256i normal[3];
  if (job.normals) {
    const __m256i nv[3] = {load_lanes(rig.normal[0], v, contiguous), load_lanes(rig.normal[1], v, contiguous),
                           load_lanes(rig.normal[2], v, contiguous)};
    for (int c = 0; c < 3; ++c) {
      const __m256i rn = add(add(mul(rot[c][0], nv[0]), mul(rot[c][1], nv[1])), mul(rot[c][2], nv[2]));
      normal[c] = sat_i32_epi64(round_shift_epi64<fx::kUnitFracBits>(rn));
    }
  }
  for (int c = 0; c < 3; ++c) {
    store_lanes(out.position[c], position[c], index, n, contiguous);
    if (job.normals) store_lanes(out.normal[c], normal[c], index, n, contiguous);
  }
  uint32_t bad = checks.bad_lanes() & ((1u << n) - 1);
  while (bad != 0) {
    const uint32_t l = static_cast<uint32_t>(__builtin_ctz(bad));
    bad &= bad - 1;
    skin_dual_vertex(rig, job.dual, v[l], out, index[l], true);
  }
}

template <uint32_t K>
void run_dual(const DualJob& job, uint32_t count) {
  const rig::Rig& rig = *job.rig;
  uint32_t v[kLanes];
  uint32_t n = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t vertex = job.first + i;
    if (rig.method[vertex] != static_cast<uint8_t>(rig::SkinMethod::kDualQuaternion)) continue;
    v[n++] = vertex;
    if (n == kLanes) {
      dual_group<K>(job, v, n);
      n = 0;
    }
  }
  if (n == 0) return;
  for (uint32_t l = n; l < kLanes; ++l) v[l] = v[n - 1];  // spare lanes: computed, not stored
  dual_group<K>(job, v, n);
}

}  // namespace

void skin_dual_avx2(const rig::Rig& rig, std::span<const fx::DualQuat> dual, uint32_t first, uint32_t count,
                    const SkinnedVertices& out) {
  // The plain hemisphere dot needs a near-unit palette: checked once per call.
  if (!dual_palette_near_unit(dual)) return skin_dual_scalar(rig, dual, first, count, out);
  const DualJob job{&rig, dual, &out, first, !out.normal[0].empty() && !rig.normal[0].empty()};
  switch (rig.influences_per_vertex) {
    case 1:
      return run_dual<1>(job, count);
    case 2:
      return run_dual<2>(job, count);
    case 3:
      return run_dual<3>(job, count);
    case 4:
      return run_dual<4>(job, count);
    case 5:
      return run_dual<5>(job, count);
    case 6:
      return run_dual<6>(job, count);
    case 7:
      return run_dual<7>(job, count);
    case 8:
      return run_dual<8>(job, count);
    default:
      return skin_dual_scalar(rig, dual, first, count, out);
  }
}

}  // namespace sinew::skin::detail
