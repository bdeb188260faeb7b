// Unit dual quaternions for dual-quaternion skinning (Kavan et al.):
// real part a rotation (Q2.30), dual part 0.5 * t * real with t in Len, so the
// dual components carry the Len format (Q12.20).
#pragma once

#include "mat34.hpp"
#include "rsqrt_fast.hpp"

namespace sinew::fx {

struct DualQuat {
  Quat real;  // Q2.30
  Quat dual;  // Q12.20 (Len) components
};

DualQuat dual_quat_from_rt(const Quat& rotation, Vec3 translation);

// Normalises a blended dual quaternion: both parts divided by |real| and the
// dual part's component along real removed (so real . dual = 0). Returns false
// (and identity) for a zero real part.
bool normalize(DualQuat* dq);

// The same, division-free (rsqrt_fast): for per-vertex blends in skinning.
// Inline: it runs once per skinned vertex. Zero real parts and squared norms
// above 2^63 (far from any blend of unit quaternions) take normalize().
inline bool normalize_fast(DualQuat* dq) {
  const int64_t w = dq->real.w, x = dq->real.x, y = dq->real.y, z = dq->real.z;
  const uint64_t n2 = static_cast<uint64_t>(w * w) + static_cast<uint64_t>(x * x) + static_cast<uint64_t>(y * y) +
                      static_cast<uint64_t>(z * z);
  if (n2 == 0 || n2 > (uint64_t{1} << 63)) return normalize(dq);
  const RsqrtResult r = rsqrt_fast(n2);
  // c / |real|: real components scaled to Q30, dual components stay Q20.
  // |real| = sqrt(n2) / 2^30, so c / |real| = c * y * 2^(half_shift - 61) * 2^30.
  const int shift = 31 - r.half_shift;
  const auto div = [&](int32_t c) {
    const int64_t p = int64_t{c} * r.y;
    return sat_i32(shift > 0 ? round_shift(p, shift) : p);
  };
  const Quat rq{div(dq->real.w), div(dq->real.x), div(dq->real.y), div(dq->real.z)};
  Quat d{div(dq->dual.w), div(dq->dual.x), div(dq->dual.y), div(dq->dual.z)};
  // rq . d without saturation: each Newton step of rsqrt_fast gives at most
  // y_exact + 3 (y (3 - v y^2) / 2 <= 1 / sqrt(v), plus the floors), so |rq|
  // < 2^30 + 8 and |rq . d| <= |rq| |d| < (2^30 + 8) 2^32 < 2^63 by
  // Cauchy-Schwarz, for every partial sum too: the plain sum is dot_wide.
  const int64_t rd = int64_t{rq.w} * d.w + int64_t{rq.x} * d.x + int64_t{rq.y} * d.y + int64_t{rq.z} * d.z;
  const int32_t k = sat_i32(round_shift(rd, kUnitFracBits));
  d.w = sub_sat(d.w, mul_by_unit(k, rq.w));
  d.x = sub_sat(d.x, mul_by_unit(k, rq.x));
  d.y = sub_sat(d.y, mul_by_unit(k, rq.y));
  d.z = sub_sat(d.z, mul_by_unit(k, rq.z));
  dq->real = rq;
  dq->dual = d;
  return true;
}

// Translation encoded by a unit dual quaternion: 2 * dual * conj(real).
Vec3 translation_of(const DualQuat& dq);

// Applies a unit dual quaternion to a Len point: R p + t.
Vec3 transform_point(const DualQuat& dq, Vec3 p);

}  // namespace sinew::fx
