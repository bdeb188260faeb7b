// Quaternions with Q2.30 components (w + xi + yj + zk), Hamilton convention,
// rotating vectors as q v q*. Unit quaternions keep |component| <= 1, so
// products stay exact in int64 before one final rounding per component.
#pragma once

#include "trig.hpp"
#include "vec3.hpp"

namespace sinew::fx {

struct Quat {
  Unit w, x, y, z;
  friend constexpr bool operator==(const Quat&, const Quat&) = default;
};

inline constexpr Quat quat_identity() { return {kUnitOne, 0, 0, 0}; }

// Hamilton product a*b, each component the correctly rounded sum of four exact
// products (saturating on inputs outside the unit range).
Quat mul(const Quat& a, const Quat& b);

inline constexpr Quat conjugate(const Quat& q) { return {q.w, neg_sat(q.x), neg_sat(q.y), neg_sat(q.z)}; }
inline constexpr Quat negate(const Quat& q) { return {neg_sat(q.w), neg_sat(q.x), neg_sat(q.y), neg_sat(q.z)}; }

// Four-component dot product in Q4.60 (saturating).
int64_t dot_wide(const Quat& a, const Quat& b);

// Rotation of `angle` about a Q2.30 unit axis.
Quat quat_from_axis_angle(Vec3 unit_axis, Angle angle);

// Rescales to unit length. The zero quaternion becomes identity and returns false.
bool normalize(Quat* q);

// Rotates any-format vector v by unit quaternion q (exact-rounded per component
// of the rotation-matrix form).
Vec3 rotate(const Quat& q, Vec3 v);

// Normalised linear interpolation on the shorter arc, t in Q2.30 [0, 1].
Quat nlerp(const Quat& a, const Quat& b, Unit t);

}  // namespace sinew::fx
