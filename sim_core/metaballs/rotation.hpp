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

#include "sim_core/fixed/mat34.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"

namespace sinew::metaballs::detail {

// (1 - t) a + t b on a's hemisphere, renormalised with rsqrt_fast; t in Q2.30
// [0, 1].
inline fx::Quat nlerp_fast(const fx::Quat& a, const fx::Quat& b, fx::Unit t) {
  if (t == 0) return a;
  const int64_t sign = fx::dot_wide(a, b) < 0 ? -1 : 1;
  const int64_t s = fx::kUnitOne - int64_t{t}, u = sign * t;
  const int64_t c[4] = {s * a.w + u * b.w, s * a.x + u * b.x, s * a.y + u * b.y,
                        s * a.z + u * b.z};  // Q60, |c| <= 2^60
  int64_t q[4];
  uint64_t n2 = 0;
  for (int i = 0; i < 4; ++i) {
    q[i] = fx::round_shift(c[i], fx::kUnitFracBits);  // Q30
    n2 += static_cast<uint64_t>(q[i] * q[i]);
  }
  if (n2 == 0)
    return a;  // antipodal halves cancel: keep a (only at t = 1/2 of a
               // 360-degree gap)
  const fx::RsqrtResult r = fx::rsqrt_fast(n2);
  // q / |q| in Q30: q * y * 2^(half_shift - 61) * 2^30.
  const int shift = 31 - r.half_shift;
  const auto n = [&](int64_t v) { return fx::sat_i32(shift > 0 ? fx::round_shift(v * r.y, shift) : v * r.y); };
  return {n(q[0]), n(q[1]), n(q[2]), n(q[3])};
}

// R d for a Len vector d (|d| < 2^30), exact in Q50.
inline void rotate_q50(const fx::Rot3& r, fx::Vec3 d, int64_t out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = int64_t{r.m[i][0]} * d.x + int64_t{r.m[i][1]} * d.y + int64_t{r.m[i][2]} * d.z;
}

}  // namespace sinew::metaballs::detail
