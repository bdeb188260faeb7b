// 3-vectors of int32 fixed-point components (Len positions, Unit directions).
#pragma once

#include <cstdint>

#include "scalar.hpp"

namespace sinew::fx {

struct Vec3 {
  int32_t x, y, z;
  friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

inline constexpr Vec3 add(Vec3 a, Vec3 b) { return {add_sat(a.x, b.x), add_sat(a.y, b.y), add_sat(a.z, b.z)}; }
inline constexpr Vec3 sub(Vec3 a, Vec3 b) { return {sub_sat(a.x, b.x), sub_sat(a.y, b.y), sub_sat(a.z, b.z)}; }
// Scales any-format vector by a Q2.30 factor.
inline constexpr Vec3 scale(Vec3 v, Unit s) { return {mul_by_unit(v.x, s), mul_by_unit(v.y, s), mul_by_unit(v.z, s)}; }
// Exact dot product, in the sum of both operands' fractional bits. Each
// product is < 2^62 in magnitude; the sum saturates instead of overflowing.
inline constexpr int64_t dot_wide(Vec3 a, Vec3 b) {
  return add_sat_i64(add_sat_i64(int64_t{a.x} * b.x, int64_t{a.y} * b.y), int64_t{a.z} * b.z);
}
// Cross product of two vectors, result shifted right by `shift` with rounding.
inline constexpr Vec3 cross(Vec3 a, Vec3 b, int shift) {
  return {sat_i32(round_shift(int64_t{a.y} * b.z - int64_t{a.z} * b.y, shift)),
          sat_i32(round_shift(int64_t{a.z} * b.x - int64_t{a.x} * b.z, shift)),
          sat_i32(round_shift(int64_t{a.x} * b.y - int64_t{a.y} * b.x, shift))};
}

// Unit-length direction (Q2.30) of any int32 vector; false (and zero) for the
// zero vector. Works for any magnitude: the vector is first shifted so its
// largest component lies in [2^29, 2^30).
bool normalize_to_unit(Vec3 v, Vec3* out);

// Euclidean length, exact floor, in the vector's own format.
uint32_t length(Vec3 v);

}  // namespace sinew::fx
