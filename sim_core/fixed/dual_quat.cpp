#include "dual_quat.hpp"

#include "norm.hpp"

namespace sinew::fx {

DualQuat dual_quat_from_rt(const Quat& rotation, Vec3 translation) {
  // dual = 0.5 * (0, t) * real: Len x Unit products, halved in the rounding.
  const Quat t{0, translation.x, translation.y, translation.z};
  const Quat full = mul(t, rotation);  // mul rounds Q(20+30) back to Q20
  const auto half = [](int32_t v) { return static_cast<int32_t>(round_shift(v, 1)); };
  return {rotation, {half(full.w), half(full.x), half(full.y), half(full.z)}};
}

bool normalize(DualQuat* dq) {
  const int32_t c[4] = {dq->real.w, dq->real.x, dq->real.y, dq->real.z};
  const NormDivisor n = norm_divisor(c, 4);
  if (n.length == 0) {
    *dq = {quat_identity(), {0, 0, 0, 0}};
    return false;
  }
  const auto div = [&](int32_t v) { return divide_by_norm(v, n); };
  const Quat r{div(dq->real.w), div(dq->real.x), div(dq->real.y), div(dq->real.z)};
  // Dual components are Len: divide_by_norm gives dual / |real|, still in Q12.20.
  Quat d{div(dq->dual.w), div(dq->dual.x), div(dq->dual.y), div(dq->dual.z)};
  // Remove the dual part's projection on the real part: d -= (r . d) r.
  const int32_t k = sat_i32(round_shift(dot_wide(r, d), kUnitFracBits));  // Q20
  d.w = sub_sat(d.w, mul_by_unit(k, r.w));
  d.x = sub_sat(d.x, mul_by_unit(k, r.x));
  d.y = sub_sat(d.y, mul_by_unit(k, r.y));
  d.z = sub_sat(d.z, mul_by_unit(k, r.z));
  dq->real = r;
  dq->dual = d;
  return true;
}

Vec3 translation_of(const DualQuat& dq) {
  const Quat t = mul(dq.dual, conjugate(dq.real));  // Q20 components
  return {sat_i32(int64_t{t.x} * 2), sat_i32(int64_t{t.y} * 2), sat_i32(int64_t{t.z} * 2)};
}

Vec3 transform_point(const DualQuat& dq, Vec3 p) { return add(rotate(dq.real, p), translation_of(dq)); }

}  // namespace sinew::fx
