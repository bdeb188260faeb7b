#include "mat34.hpp"

namespace sinew::fx {
namespace {

using detail::narrow;
using detail::sum3;

}  // namespace

Mat34 mat34_identity() { return {{{kLinOne, 0, 0}, {0, kLinOne, 0}, {0, 0, kLinOne}}, {0, 0, 0}}; }

Rot3 rot3_from_quat(const Quat& q) {
  const int64_t w = q.w, x = q.x, y = q.y, z = q.z;
  const int64_t one = int64_t{1} << 60;
  // Entries in Q4.60: 1 - 2(..) and 2(..); products of unit components < 2^60.
  const auto e = [&](int64_t v) { return narrow(v, kUnitFracBits); };
  const auto twice = [](int64_t a, int64_t b) {
    const int64_t sum = add_sat_i64(a, b);
    return add_sat_i64(sum, sum);
  };
  Rot3 r{};
  r.m[0][0] = e(add_sat_i64(one, -twice(y * y, z * z)));
  r.m[0][1] = e(twice(x * y, -(w * z)));
  r.m[0][2] = e(twice(x * z, w * y));
  r.m[1][0] = e(twice(x * y, w * z));
  r.m[1][1] = e(add_sat_i64(one, -twice(x * x, z * z)));
  r.m[1][2] = e(twice(y * z, -(w * x)));
  r.m[2][0] = e(twice(x * z, -(w * y)));
  r.m[2][1] = e(twice(y * z, w * x));
  r.m[2][2] = e(add_sat_i64(one, -twice(x * x, y * y)));
  return r;
}

Mat34 mat34_from_trs(Vec3 translation, const Quat& rotation, Vec3 scale_lin) {
  const Rot3 r = rot3_from_quat(rotation);
  const int32_t s[3] = {scale_lin.x, scale_lin.y, scale_lin.z};
  Mat34 out{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out.m[i][j] = narrow(int64_t{r.m[i][j]} * s[j], kUnitFracBits);
  out.t[0] = translation.x;
  out.t[1] = translation.y;
  out.t[2] = translation.z;
  return out;
}

Mat34 mul(const Mat34& a, const Mat34& b) {
  Mat34 out{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      out.m[i][j] =
          narrow(sum3(int64_t{a.m[i][0]} * b.m[0][j], int64_t{a.m[i][1]} * b.m[1][j], int64_t{a.m[i][2]} * b.m[2][j]),
                 kLinFracBits);
    }
    // a.m (Q24) * b.t (Q20) -> Q44; a.t (Q20) lifted to Q44 exactly; one rounding.
    const int64_t lin = sum3(int64_t{a.m[i][0]} * b.t[0], int64_t{a.m[i][1]} * b.t[1], int64_t{a.m[i][2]} * b.t[2]);
    out.t[i] = narrow(add_sat_i64(lin, int64_t{a.t[i]} * (int64_t{1} << kLinFracBits)), kLinFracBits);
  }
  return out;
}

Vec3 rotate(const Rot3& r, Vec3 v) {
  int32_t out[3];
  for (int i = 0; i < 3; ++i) {
    out[i] = narrow(sum3(int64_t{r.m[i][0]} * v.x, int64_t{r.m[i][1]} * v.y, int64_t{r.m[i][2]} * v.z), kUnitFracBits);
  }
  return {out[0], out[1], out[2]};
}

}  // namespace sinew::fx
