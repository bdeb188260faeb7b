// Property-based tests (rapidcheck) of the fixed-point algebra.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cstdlib>

#include "sim_core/fixed/dual_quat.hpp"
#include "sim_core/fixed/sqrt.hpp"

namespace fx = sinew::fx;

namespace {
fx::Quat unit_quat(int32_t ax, int32_t ay, int32_t az, uint32_t angle) {
  fx::Vec3 u;
  if (!fx::normalize_to_unit({ax, ay, az}, &u)) u = {fx::kUnitOne, 0, 0};
  return fx::quat_from_axis_angle(u, angle);
}
}  // namespace

RC_GTEST_PROP(FixedProperties, IsqrtBracketsItsInput, (uint64_t v)) {
  const uint64_t r = fx::isqrt_u64(v);
  RC_ASSERT(r * r <= v);
  if (r < 0xFFFFFFFFu) RC_ASSERT((r + 1) * (r + 1) > v);
}

RC_GTEST_PROP(FixedProperties, SinSquaredPlusCosSquaredIsOne, (uint32_t a)) {
  const fx::SinCos sc = fx::sin_cos(a);
  const int64_t n = int64_t{sc.sin} * sc.sin + int64_t{sc.cos} * sc.cos;
  RC_ASSERT(std::llabs(n - (int64_t{1} << 60)) <= (int64_t{4} << 30));
}

RC_GTEST_PROP(FixedProperties, Atan2InvertsSinCos, (uint32_t a)) {
  const fx::SinCos sc = fx::sin_cos(a);
  const int32_t diff = static_cast<int32_t>(fx::atan2_angle(sc.sin, sc.cos) - a);
  RC_ASSERT(std::abs(diff) <= 8);  // Q2.30 inputs resolve the angle to ~4 LSB
}

RC_GTEST_PROP(FixedProperties, RotationPreservesLength,
              (int32_t ax, int32_t ay, int32_t az, uint32_t angle, int32_t px, int32_t py, int32_t pz)) {
  const fx::Quat q = unit_quat(ax, ay, az, angle);
  const fx::Vec3 p{px >> 2, py >> 2, pz >> 2};
  const int64_t before = fx::length(p);
  const int64_t after = fx::length(fx::rotate(q, p));
  RC_ASSERT(std::llabs(before - after) <= 4);
}

RC_GTEST_PROP(FixedProperties, QuatTimesConjugateIsIdentity, (int32_t ax, int32_t ay, int32_t az, uint32_t angle)) {
  const fx::Quat q = unit_quat(ax, ay, az, angle);
  const fx::Quat r = fx::mul(q, fx::conjugate(q));
  RC_ASSERT(std::abs(r.w - fx::kUnitOne) <= 4);
  RC_ASSERT(std::abs(r.x) <= 4);
}

RC_GTEST_PROP(FixedProperties, MatrixProductIsAssociativeWithinRounding,
              (uint32_t a1, uint32_t a2, int32_t t1, int32_t t2, int32_t px)) {
  const fx::Mat34 a = fx::mat34_from_quat(unit_quat(1 << 20, 3, -7, a1), {t1 >> 8, 0, 5});
  const fx::Mat34 b = fx::mat34_from_quat(unit_quat(2, 1 << 20, 9, a2), {0, t2 >> 8, -5});
  const fx::Vec3 p{px >> 8, 12345, -999};
  const fx::Vec3 once = fx::transform_point(fx::mul(a, b), p);
  const fx::Vec3 twice = fx::transform_point(a, fx::transform_point(b, p));
  RC_ASSERT(std::abs(once.x - twice.x) <= 64);
  RC_ASSERT(std::abs(once.y - twice.y) <= 64);
}

RC_GTEST_PROP(FixedProperties, NormalizedQuatHasUnitNorm, (int32_t w, int32_t x, int32_t y, int32_t z)) {
  fx::Quat q{w, x, y, z};
  if (!fx::normalize(&q)) return;
  const int64_t n2 = fx::dot_wide(q, q);
  RC_ASSERT(std::llabs(n2 - (int64_t{1} << 60)) <= (int64_t{8} << 30));
}
