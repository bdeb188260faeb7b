// Rotation helpers of the metaballs layer: division-free nlerp and the
// rotation matrix of a (near-)unit quaternion.
//
// Rotations are blended by normalised linear interpolation rather than slerp:
// on the two-rotation blends used here nlerp follows the same great arc as
// slerp (only the speed along it differs, by < 4 degrees at a 90 degree
// gap), needs no trigonometry, and is commutative when more than two
// rotations are blended — the paper's Slerp is a choice of smoothness, not of
// the path.
#pragma once

#include "sim_core/fixed/dual_quat.hpp"
#include "sim_core/fixed/mat34.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"

namespace sinew::metaballs::detail {

// Whether the exact dot product of a and b is negative (the hemisphere test;
// fx::dot_wide's sign, without its call and saturation): each product split
// into a quarter (floor) and its remainder, so no sum overflows.
inline bool dot_negative(const fx::Quat& a, const fx::Quat& b) {
  const int64_t p[4] = {int64_t{a.w} * b.w, int64_t{a.x} * b.x, int64_t{a.y} * b.y, int64_t{a.z} * b.z};
  int64_t quarters = 0, remainders = 0;  // dot = 4 quarters + remainders, remainders in [0, 12]
  for (const int64_t x : p) quarters += x >> 2, remainders += x & 3;
  if (quarters >= 0) return false;
  if (quarters < -3) return true;
  return 4 * quarters + remainders < 0;
}

// A weighted sum of unit quaternions, each taken on the first's hemisphere,
// renormalised with rsqrt_fast: nlerp of two or more rotations. Weights are
// Q2.30 and sum to at most 2^30, so every Q60 component stays within 2^60.
struct QuatBlend {
  int64_t c[4] = {0, 0, 0, 0};  // Q60
  fx::Quat first{};
  bool any = false;

  void add(const fx::Quat& q, fx::Unit w) {
    if (!any) first = q, any = true;
    const int64_t u = dot_negative(first, q) ? -int64_t{w} : int64_t{w};
    c[0] += u * q.w, c[1] += u * q.x, c[2] += u * q.y, c[3] += u * q.z;
  }

  fx::Quat unit() const {
    int64_t q[4];
    uint64_t n2 = 0;
    for (int i = 0; i < 4; ++i) {
      q[i] = fx::round_shift(c[i], fx::kUnitFracBits);  // Q30
      n2 += static_cast<uint64_t>(q[i] * q[i]);
    }
    if (n2 == 0) return first;  // antipodal halves cancel (a 360-degree gap): keep the first
    const fx::RsqrtResult r = fx::rsqrt_fast(n2);
    // q / |q| in Q30: q * y * 2^(half_shift - 61) * 2^30.
    const int shift = 31 - r.half_shift;
    const auto n = [&](int64_t v) { return fx::sat_i32(shift > 0 ? fx::round_shift(v * r.y, shift) : v * r.y); };
    return {n(q[0]), n(q[1]), n(q[2]), n(q[3])};
  }
};

// Weighted rigid motions blended as dual quaternions (Kavan et al.), each on
// the first's hemisphere, normalised: the rigid motion on the arc that eq.
// (2) and eq. (4) take where their rotations differ (docs/metaballs.md,
// "Balls of two bones"). Weights Q2.30 summing to 1; unit quaternions, so
// every weighted sum stays far below 2^63.
struct DualQuatBlend {
  int64_t real[4] = {0, 0, 0, 0}, dual[4] = {0, 0, 0, 0};  // Q60, Q50
  fx::Quat first{};
  bool any = false;

  void add(const fx::DualQuat& d, fx::Unit w) {
    if (!any) first = d.real, any = true;
    const int64_t u = dot_negative(first, d.real) ? -int64_t{w} : int64_t{w};
    const int32_t r[4] = {d.real.w, d.real.x, d.real.y, d.real.z}, e[4] = {d.dual.w, d.dual.x, d.dual.y, d.dual.z};
    for (int c = 0; c < 4; ++c) {
      real[c] += u * r[c];
      dual[c] += u * e[c];
    }
  }

  fx::DualQuat unit() const {
    const auto q30 = [](int64_t x) { return fx::sat_i32(fx::round_shift(x, fx::kUnitFracBits)); };
    fx::DualQuat dq{{q30(real[0]), q30(real[1]), q30(real[2]), q30(real[3])},
                    {q30(dual[0]), q30(dual[1]), q30(dual[2]), q30(dual[3])}};
    fx::normalize_fast(&dq);
    return dq;
  }
};

// (1 - t) a + t b on a's hemisphere, renormalised; t in Q2.30 [0, 1]. The
// ends and equal rotations return an input unchanged.
inline fx::Quat nlerp_fast(const fx::Quat& a, const fx::Quat& b, fx::Unit t) {
  if (t == 0 || a == b) return a;
  if (t == fx::kUnitOne) return b;
  QuatBlend s;
  s.add(a, fx::kUnitOne - t);
  s.add(b, t);
  return s.unit();
}

// R d for a Len vector d (|d| < 2^30), exact in Q50.
inline void rotate_q50(const fx::Rot3& r, fx::Vec3 d, int64_t out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = int64_t{r.m[i][0]} * d.x + int64_t{r.m[i][1]} * d.y + int64_t{r.m[i][2]} * d.z;
}

}  // namespace sinew::metaballs::detail
