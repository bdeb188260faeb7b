// Affine 3x4 transforms p' = M p + t, column-vector convention (as glTF).
// Linear part in Q8.24 (rotation times scale, |entry| < 128), translation in
// Q12.20 rig units. Rot3 is a pure rotation in Q2.30 for unit quantities.
#pragma once

#include "quat.hpp"

namespace sinew::fx {

struct Mat34 {
  Lin m[3][3];  // row-major
  Len t[3];
  friend constexpr bool operator==(const Mat34&, const Mat34&) = default;
};

struct Rot3 {
  Unit m[3][3];  // row-major, Q2.30
};

Mat34 mat34_identity();

// Rotation matrix of a unit quaternion, each entry correctly rounded from the
// exact Q4.60 expression (e.g. m00 = 1 - 2(y^2 + z^2)).
Rot3 rot3_from_quat(const Quat& q);

// T * R * S: translation (Len), rotation, per-axis scale (Q8.24).
// Rotation matrix entries from exact Q60 products rounded once (components
// within a few LSB of unit length: no saturation needed).
inline Rot3 rot3_of_unit(const Quat& q) {
  const int64_t w = q.w, x = q.x, y = q.y, z = q.z;
  const int64_t one = int64_t{1} << 60;
  const auto e = [](int64_t v) { return sat_i32(round_shift(v, kUnitFracBits)); };
  Rot3 r;
  r.m[0][0] = e(one - 2 * (y * y + z * z));
  r.m[0][1] = e(2 * (x * y - w * z));
  r.m[0][2] = e(2 * (x * z + w * y));
  r.m[1][0] = e(2 * (x * y + w * z));
  r.m[1][1] = e(one - 2 * (x * x + z * z));
  r.m[1][2] = e(2 * (y * z - w * x));
  r.m[2][0] = e(2 * (x * z - w * y));
  r.m[2][1] = e(2 * (y * z + w * x));
  r.m[2][2] = e(one - 2 * (x * x + y * y));
  return r;
}

Mat34 mat34_from_trs(Vec3 translation, const Quat& rotation, Vec3 scale_lin);
inline Mat34 mat34_from_quat(const Quat& q, Vec3 translation) {
  return mat34_from_trs(translation, q, {kLinOne, kLinOne, kLinOne});
}

// a * b. Each entry is the correctly rounded sum of exact products
// (saturating, never overflowing, outside the documented ranges).
Mat34 mul(const Mat34& a, const Mat34& b);

namespace detail {

inline int64_t sum3(int64_t a, int64_t b, int64_t c) { return add_sat_i64(add_sat_i64(a, b), c); }

// Rounds v / 2^s half up without overflowing near the saturated extremes.
inline int32_t narrow(int64_t v, int s) {
  if (v > INT64_MAX - (int64_t{1} << (s - 1))) return INT32_MAX;
  return sat_i32(round_shift(v, s));
}

}  // namespace detail

// M p + t for a Len point. Inline: the layers call it per vertex and node.
inline Vec3 transform_point(const Mat34& a, Vec3 p) {
  int32_t out[3];
  for (int i = 0; i < 3; ++i) {
    const int64_t lin = detail::sum3(int64_t{a.m[i][0]} * p.x, int64_t{a.m[i][1]} * p.y, int64_t{a.m[i][2]} * p.z);
    out[i] = detail::narrow(add_sat_i64(lin, int64_t{a.t[i]} * (int64_t{1} << kLinFracBits)), kLinFracBits);
  }
  return {out[0], out[1], out[2]};
}
// M v for a vector of any format (normals, directions).
inline Vec3 transform_vector(const Mat34& a, Vec3 v) {
  int32_t out[3];
  for (int i = 0; i < 3; ++i)
    out[i] = detail::narrow(detail::sum3(int64_t{a.m[i][0]} * v.x, int64_t{a.m[i][1]} * v.y, int64_t{a.m[i][2]} * v.z),
                            kLinFracBits);
  return {out[0], out[1], out[2]};
}
// R v for a vector of any format.
Vec3 rotate(const Rot3& r, Vec3 v);

// transform_point and transform_vector from plain 64-bit sums, for inputs
// whose bound rules out every saturation: then the same words, without the
// overflow tests (the per-node and per-vertex loops of the layers).
// A point with every |component| < 2^29 (512 rig units): each product
// |m p| < 2^31 2^29 = 2^60, a row with the translation term (< 2^55) stays
// below 2^62, so neither sum3's saturation nor narrow's guard can act.
inline constexpr int32_t kPlainPointLimit = (int32_t{1} << 29) - 1;
// A vector with every |component| <= 2^30 + 2^28 (a Q2.30 direction): each
// product is at most 2^31 (2^30 + 2^28) and a row at most 3.75 2^61, below
// 2^63 - 2^23.
inline constexpr int32_t kPlainVectorLimit = (int32_t{1} << 30) + (int32_t{1} << 28);

// Every |component| <= limit.
inline bool within(Vec3 v, int32_t limit) {
  const auto inside = [limit](int32_t c) { return c <= limit && c >= -limit; };
  return inside(v.x) && inside(v.y) && inside(v.z);
}

// transform_point(a, p) for within(p, kPlainPointLimit).
inline Vec3 transform_point_plain(const Mat34& a, Vec3 p) {
  int32_t out[3];
  for (int i = 0; i < 3; ++i) {
    const int64_t row = int64_t{a.m[i][0]} * p.x + int64_t{a.m[i][1]} * p.y + int64_t{a.m[i][2]} * p.z +
                        int64_t{a.t[i]} * (int64_t{1} << kLinFracBits);
    out[i] = sat_i32(round_shift(row, kLinFracBits));
  }
  return {out[0], out[1], out[2]};
}
// transform_vector(a, v) for within(v, kPlainVectorLimit).
inline Vec3 transform_vector_plain(const Mat34& a, Vec3 v) {
  int32_t out[3];
  for (int i = 0; i < 3; ++i) {
    const int64_t row = int64_t{a.m[i][0]} * v.x + int64_t{a.m[i][1]} * v.y + int64_t{a.m[i][2]} * v.z;
    out[i] = sat_i32(round_shift(row, kLinFracBits));
  }
  return {out[0], out[1], out[2]};
}

}  // namespace sinew::fx
