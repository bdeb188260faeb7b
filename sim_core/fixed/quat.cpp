#include "quat.hpp"

#include "mat34.hpp"
#include "norm.hpp"

namespace sinew::fx {
namespace {

inline int64_t sum4(int64_t a, int64_t b, int64_t c, int64_t d) {
  return add_sat_i64(add_sat_i64(a, b), add_sat_i64(c, d));
}

// Q4.60 -> Q2.30, rounded half up; saturated sums near INT64_MAX stay defined.
inline Unit round_q60(int64_t v) {
  if (v > INT64_MAX - (int64_t{1} << 29)) return INT32_MAX;
  return sat_i32(round_shift(v, kUnitFracBits));
}

}  // namespace

Quat mul(const Quat& a, const Quat& b) {
  const int64_t aw = a.w, ax = a.x, ay = a.y, az = a.z;
  const int64_t bw = b.w, bx = b.x, by = b.y, bz = b.z;
  return {round_q60(sum4(aw * bw, -(ax * bx), -(ay * by), -(az * bz))),
          round_q60(sum4(aw * bx, ax * bw, ay * bz, -(az * by))),
          round_q60(sum4(aw * by, -(ax * bz), ay * bw, az * bx)),
          round_q60(sum4(aw * bz, ax * by, -(ay * bx), az * bw))};
}

int64_t dot_wide(const Quat& a, const Quat& b) {
  return sum4(int64_t{a.w} * b.w, int64_t{a.x} * b.x, int64_t{a.y} * b.y, int64_t{a.z} * b.z);
}

Quat quat_from_axis_angle(Vec3 unit_axis, Angle angle) {
  const SinCos h = sin_cos(angle >> 1);  // half angle; q and -q are one rotation
  return {h.cos, mul_unit(unit_axis.x, h.sin), mul_unit(unit_axis.y, h.sin), mul_unit(unit_axis.z, h.sin)};
}

bool normalize(Quat* q) {
  const int32_t c[4] = {q->w, q->x, q->y, q->z};
  const NormDivisor d = norm_divisor(c, 4);
  if (d.length == 0) {
    *q = quat_identity();
    return false;
  }
  *q = {divide_by_norm(q->w, d), divide_by_norm(q->x, d), divide_by_norm(q->y, d), divide_by_norm(q->z, d)};
  return true;
}

Vec3 rotate(const Quat& q, Vec3 v) { return rotate(rot3_from_quat(q), v); }

Quat nlerp(const Quat& a, const Quat& b, Unit t) {
  const Quat bb = dot_wide(a, b) < 0 ? negate(b) : b;
  const Unit s = sat_i32(int64_t{kUnitOne} - t);
  const auto mix = [&](Unit p, Unit q) { return round_q60(add_sat_i64(int64_t{p} * s, int64_t{q} * t)); };
  Quat r{mix(a.w, bb.w), mix(a.x, bb.x), mix(a.y, bb.y), mix(a.z, bb.z)};
  normalize(&r);
  return r;
}

}  // namespace sinew::fx
