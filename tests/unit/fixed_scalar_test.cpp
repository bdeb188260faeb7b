#include <gtest/gtest.h>

#include "sim_core/fixed/scalar.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "sim_core/fixed/trig.hpp"
#include "sim_core/fixed/wide.hpp"

namespace fx = sinew::fx;

TEST(FixedScalar, SaturatesAndCounts) {
  fx::Saturation sat;
  EXPECT_EQ(fx::sat_i32(int64_t{1} << 40, sat), INT32_MAX);
  EXPECT_EQ(fx::sat_i32(-(int64_t{1} << 40), sat), INT32_MIN);
  EXPECT_EQ(fx::sat_i32(123, sat), 123);
  EXPECT_EQ(sat.events, 2u);
  EXPECT_EQ(fx::add_sat(INT32_MAX, 1), INT32_MAX);
  EXPECT_EQ(fx::sub_sat(INT32_MIN, 1), INT32_MIN);
  EXPECT_EQ(fx::neg_sat(INT32_MIN), INT32_MAX);
  EXPECT_EQ(fx::add_sat_i64(INT64_MAX, 5), INT64_MAX);
  EXPECT_EQ(fx::add_sat_i64(INT64_MIN, -5), INT64_MIN);
}

TEST(FixedScalar, RoundsHalfUp) {
  EXPECT_EQ(fx::round_shift(3, 1), 2);    // 1.5 -> 2
  EXPECT_EQ(fx::round_shift(-3, 1), -1);  // -1.5 -> -1 (toward +inf)
  EXPECT_EQ(fx::round_shift(-5, 1), -2);  // -2.5 -> -2
  EXPECT_EQ(fx::round_shift(5, 2), 1);    // 1.25 -> 1
  EXPECT_EQ(fx::div_round(3, 2), 2);
  EXPECT_EQ(fx::div_round(-3, 2), -1);
  EXPECT_EQ(fx::div_round(7, -2), -3);    // -3.5 -> -3
  EXPECT_EQ(fx::div_round(1, 0), 0);      // documented: zero denominator gives 0
  EXPECT_EQ(fx::mul_shift_round(3, 1, 1), 2);
  EXPECT_EQ(fx::mul_shift_round(-3, 1, 1), -1);
  EXPECT_EQ(fx::mul_shift_round(-5, 1, 1), -2);
}

TEST(FixedScalar, ProductsOfUnits) {
  EXPECT_EQ(fx::mul_unit(fx::kUnitOne, fx::kUnitOne), fx::kUnitOne);
  EXPECT_EQ(fx::mul_unit(INT32_MIN, INT32_MIN), INT32_MAX);  // (-2)^2 = 4 saturates
  EXPECT_EQ(fx::mul_unit(fx::kUnitOne / 2, -fx::kUnitOne), -fx::kUnitOne / 2);
  EXPECT_EQ(fx::requantize(fx::kLenOne, fx::kLenFracBits, fx::kLinFracBits), fx::kLinOne);
  EXPECT_EQ(fx::requantize(INT32_MAX, 20, 30), INT32_MAX);
}

TEST(FixedScalar, WideMultiplyMatchesSmallProducts) {
  const fx::U128 p = fx::mul_u64(UINT64_MAX, UINT64_MAX);
  EXPECT_EQ(p.hi, UINT64_MAX - 1);
  EXPECT_EQ(p.lo, 1u);
  EXPECT_EQ(fx::mul_shift_round(INT64_MAX, 2, 63), 2);
  EXPECT_EQ(fx::mul_shift_round(-(int64_t{1} << 40), int64_t{1} << 40, 62), -(int64_t{1} << 18));
}

TEST(FixedSqrt, ExactOnEdgesAndSquares) {
  EXPECT_EQ(fx::isqrt_u64(0), 0u);
  EXPECT_EQ(fx::isqrt_u64(1), 1u);
  EXPECT_EQ(fx::isqrt_u64(UINT64_MAX), 0xFFFFFFFFu);
  for (uint64_t r = 1; r < (uint64_t{1} << 32); r = r * 3 + 1) {
    EXPECT_EQ(fx::isqrt_u64(r * r), r);
    EXPECT_EQ(fx::isqrt_u64(r * r - 1), r - 1);
  }
  EXPECT_EQ(fx::rsqrt_q60(0), INT32_MAX);
  EXPECT_EQ(fx::rsqrt_q60(uint64_t{1} << 60), fx::kUnitOne);
  EXPECT_EQ(fx::rsqrt_q60(uint64_t{1} << 62), fx::kUnitOne / 2);
}

TEST(FixedTrig, ExactAtCardinalAngles) {
  EXPECT_EQ(fx::sin_unit(0), 0);
  EXPECT_EQ(fx::cos_unit(0), fx::kUnitOne);
  EXPECT_EQ(fx::sin_unit(fx::kQuarterTurn), fx::kUnitOne);
  EXPECT_EQ(fx::cos_unit(fx::kHalfTurn), -fx::kUnitOne);
  EXPECT_EQ(fx::sin_unit(3 * fx::kQuarterTurn), -fx::kUnitOne);
  EXPECT_EQ(fx::atan2_angle(0, 0), 0u);
  EXPECT_EQ(fx::atan2_angle(0, 5), 0u);
  EXPECT_EQ(fx::atan2_angle(5, 0), fx::kQuarterTurn);
  EXPECT_EQ(fx::atan2_angle(0, -5), fx::kHalfTurn);
  EXPECT_EQ(fx::atan2_angle(-5, 0), 3 * fx::kQuarterTurn);
  EXPECT_EQ(fx::atan2_angle(INT32_MIN, INT32_MIN), 5 * (fx::kQuarterTurn / 2));
}

TEST(FixedTrig, DegreesRoundTrip) {
  EXPECT_EQ(fx::angle_from_deg_q16(90 << 16), fx::kQuarterTurn);
  EXPECT_EQ(fx::angle_from_deg_q16(-90 << 16), 3 * fx::kQuarterTurn);
  EXPECT_EQ(fx::angle_to_deg_q16(fx::kQuarterTurn), 90 << 16);
  EXPECT_EQ(fx::angle_to_deg_q16(fx::angle_from_deg_q16(-45 << 16)), -45 << 16);
  EXPECT_EQ(fx::angle_from_deg_q16(360 << 16), 0u);  // one turn wraps
}
