// Small vector helpers of the anatomy layers, on top of sim_core/fixed.
// Every narrowing rounds half up and saturates (docs/numerics.md).
#pragma once

#include <cstdint>

#include "sim_core/fixed/vec3.hpp"

namespace sinew::muscle {

// Midpoint of two Len points, rounded half up.
inline fx::Vec3 midpoint(fx::Vec3 a, fx::Vec3 b) {
  return {fx::sat_i32(fx::round_shift(int64_t{a.x} + b.x, 1)), fx::sat_i32(fx::round_shift(int64_t{a.y} + b.y, 1)),
          fx::sat_i32(fx::round_shift(int64_t{a.z} + b.z, 1))};
}

// a + (b - a) * num / den, den > 0, 0 <= num <= den; one rounding per component.
inline fx::Vec3 lerp_ratio(fx::Vec3 a, fx::Vec3 b, int64_t num, int64_t den) {
  const auto one = [&](int32_t p, int32_t q) { return fx::sat_i32(p + fx::div_round((int64_t{q} - p) * num, den)); };
  return {one(a.x, b.x), one(a.y, b.y), one(a.z, b.z)};
}

// A Q2.30 unit direction times a length (any format) -> that format.
inline fx::Vec3 along(fx::Vec3 unit_dir, int32_t length) {
  return {fx::mul_by_unit(length, unit_dir.x), fx::mul_by_unit(length, unit_dir.y),
          fx::mul_by_unit(length, unit_dir.z)};
}

// Component of a vector (any format) along a unit direction, rounded, in
// the vector's format (64-bit: the caller saturates where it narrows).
inline int64_t component(fx::Vec3 v, fx::Vec3 unit_dir) {
  return fx::round_shift(fx::dot_wide(v, unit_dir), fx::kUnitFracBits);
}

// Unit direction of v, or `fallback` (a unit vector) for the zero vector.
inline fx::Vec3 unit_or(fx::Vec3 v, fx::Vec3 fallback, uint32_t* degenerate) {
  fx::Vec3 u;
  if (fx::normalize_to_unit(v, &u)) return u;
  ++*degenerate;
  return fallback;
}

// Cross product of two Q2.30 unit vectors, in Q2.30.
inline fx::Vec3 cross_unit(fx::Vec3 a, fx::Vec3 b) { return fx::cross(a, b, fx::kUnitFracBits); }

// A unit vector perpendicular to the unit vector z (deterministic choice).
inline fx::Vec3 any_perpendicular(fx::Vec3 z) {
  const fx::Vec3 pick =
      (z.x > fx::kUnitOne / 2 || z.x < -fx::kUnitOne / 2) ? fx::Vec3{0, fx::kUnitOne, 0} : fx::Vec3{fx::kUnitOne, 0, 0};
  fx::Vec3 u{};
  if (!fx::normalize_to_unit(cross_unit(z, pick), &u)) return fx::Vec3{0, 0, fx::kUnitOne};
  return u;
}

}  // namespace sinew::muscle
