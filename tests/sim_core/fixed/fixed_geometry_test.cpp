#include <gtest/gtest.h>

#include <cstdlib>

#include "host_tools/determinism/split_mix.hpp"
#include "sim_core/fixed/dual_quat.hpp"

namespace fx = sinew::fx;
using sinew::determinism::SplitMix64;

namespace {
fx::Quat axis_angle(fx::Vec3 axis, fx::Angle a) {
  fx::Vec3 u;
  fx::normalize_to_unit(axis, &u);
  return fx::quat_from_axis_angle(u, a);
}
int32_t max_abs_diff(fx::Vec3 a, fx::Vec3 b) {
  return std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)});
}
}  // namespace

TEST(FixedGeometry, QuarterTurnAboutZ) {
  const fx::Quat q = axis_angle({0, 0, 1}, fx::kQuarterTurn);
  const fx::Vec3 v = fx::rotate(q, fx::Vec3{fx::kLenOne, 0, 0});
  EXPECT_LE(max_abs_diff(v, {0, fx::kLenOne, 0}), 1);
}

TEST(FixedGeometry, ZeroInputsAreDefined) {
  fx::Quat q{0, 0, 0, 0};
  EXPECT_FALSE(fx::normalize(&q));
  EXPECT_EQ(q, fx::quat_identity());
  fx::Vec3 u;
  EXPECT_FALSE(fx::normalize_to_unit({0, 0, 0}, &u));
  EXPECT_EQ(u, (fx::Vec3{0, 0, 0}));
  fx::DualQuat dq{{0, 0, 0, 0}, {5, 5, 5, 5}};
  EXPECT_FALSE(fx::normalize(&dq));
}

TEST(FixedGeometry, ExtremeInputsSaturateWithoutUB) {
  const fx::Quat big{INT32_MIN, INT32_MIN, INT32_MIN, INT32_MIN};
  const fx::Quat p = fx::mul(big, big);
  EXPECT_EQ(p.w, INT32_MIN);  // -(4 * 4) clamps
  fx::Mat34 m{};
  for (auto& row : m.m)
    for (auto& e : row) e = INT32_MAX;
  m.t[0] = m.t[1] = m.t[2] = INT32_MAX;
  const fx::Vec3 r = fx::transform_point(m, {INT32_MAX, INT32_MAX, INT32_MAX});
  EXPECT_EQ(r.x, INT32_MAX);
  fx::Quat n = big;
  EXPECT_TRUE(fx::normalize(&n));
  EXPECT_EQ(n.w, -fx::kUnitOne / 2);
}

TEST(FixedGeometry, DualQuatMatchesRotationPlusTranslation) {
  SplitMix64 rng(11);
  int32_t worst = 0;
  for (int i = 0; i < 20000; ++i) {
    const fx::Quat q = axis_angle({rng.next_i32() >> 2, rng.next_i32() >> 2, rng.next_i32() >> 2}, rng.next_u32());
    const fx::Vec3 t{rng.range(-fx::kLenOne * 100, fx::kLenOne * 100), rng.range(-fx::kLenOne, fx::kLenOne),
                     rng.range(-1000, 1000)};
    const fx::Vec3 p{rng.range(-fx::kLenOne * 100, fx::kLenOne * 100), rng.range(-fx::kLenOne, fx::kLenOne), 17};
    fx::DualQuat dq = fx::dual_quat_from_rt(q, t);
    fx::normalize(&dq);
    const fx::Vec3 expect = fx::add(fx::rotate(q, p), t);
    worst = std::max(worst, max_abs_diff(fx::transform_point(dq, p), expect));
    const fx::Vec3 via_matrix = fx::transform_point(fx::mat34_from_quat(q, t), p);
    worst = std::max(worst, max_abs_diff(via_matrix, expect) / 16);  // Q8.24 rotation: 16x coarser
  }
  std::printf("numerics: %-22s worst error %d LSB of Q12.20 (|t| <= 100)\n", "dual quat transform", worst);
  EXPECT_LE(worst, 400);
}

TEST(FixedGeometry, NlerpTakesShorterArc) {
  const fx::Quat a = fx::quat_identity();
  const fx::Quat b = fx::negate(axis_angle({0, 1, 0}, fx::kQuarterTurn / 2));
  const fx::Quat m = fx::nlerp(a, b, fx::kUnitOne / 2);
  EXPECT_GT(m.w, 0);  // blended toward +b, not through the long way
  const fx::Quat half = axis_angle({0, 1, 0}, fx::kQuarterTurn / 4);
  EXPECT_LE(std::abs(m.y - half.y), 2);
}

// transform_point_plain and transform_vector_plain write transform_point's
// and transform_vector's words for every input within their limits: random
// matrices over all of int32 and inputs over the whole allowed range, and
// the corners where the sums are largest (every entry and component at its
// extreme, of equal and of opposite signs).
TEST(FixedGeometry, PlainTransformsMatchTheSaturatingOnesWithinTheirLimits) {
  SplitMix64 rng(2026);
  const auto pick = [&](int32_t limit) {
    switch (rng.next() % 4) {
      case 0:
        return limit;
      case 1:
        return -limit;
      default:
        return rng.range(-limit, limit);
    }
  };
  const auto entry = [&]() {
    switch (rng.next() % 4) {
      case 0:
        return INT32_MIN;
      case 1:
        return INT32_MAX;
      default:
        return rng.next_i32();
    }
  };
  for (int trial = 0; trial < 200000; ++trial) {
    fx::Mat34 m{};
    for (auto& row : m.m)
      for (auto& e : row) e = entry();
    for (auto& t : m.t) t = entry();
    const fx::Vec3 p{pick(fx::kPlainPointLimit), pick(fx::kPlainPointLimit), pick(fx::kPlainPointLimit)};
    const fx::Vec3 v{pick(fx::kPlainVectorLimit), pick(fx::kPlainVectorLimit), pick(fx::kPlainVectorLimit)};
    ASSERT_TRUE(fx::within(p, fx::kPlainPointLimit) && fx::within(v, fx::kPlainVectorLimit));
    ASSERT_EQ(fx::transform_point_plain(m, p), fx::transform_point(m, p)) << trial;
    ASSERT_EQ(fx::transform_vector_plain(m, v), fx::transform_vector(m, v)) << trial;
  }
  EXPECT_FALSE(fx::within({fx::kPlainPointLimit + 1, 0, 0}, fx::kPlainPointLimit));
  EXPECT_FALSE(fx::within({0, 0, -fx::kPlainVectorLimit - 1}, fx::kPlainVectorLimit));
}
