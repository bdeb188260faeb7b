// Unit dual quaternions for dual-quaternion skinning (Kavan et al.):
// real part a rotation (Q2.30), dual part 0.5 * t * real with t in Len, so the
// dual components carry the Len format (Q12.20).
#pragma once

#include "mat34.hpp"

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
bool normalize_fast(DualQuat* dq);

// Translation encoded by a unit dual quaternion: 2 * dual * conj(real).
Vec3 translation_of(const DualQuat& dq);

// Applies a unit dual quaternion to a Len point: R p + t.
Vec3 transform_point(const DualQuat& dq, Vec3 p);

}  // namespace sinew::fx
