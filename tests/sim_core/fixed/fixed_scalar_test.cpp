#include <gtest/gtest.h>

#include "sim_core/fixed/rsqrt_fast.hpp"
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
  EXPECT_EQ(fx::div_round(7, -2), -3);  // -3.5 -> -3
  EXPECT_EQ(fx::div_round(1, 0), 0);    // documented: zero denominator gives 0
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

// The one-multiply form (where a 128-bit type exists) against the
// magnitudes' form armhf runs: the same bits for every sign, shift and
// width, the int64 limits included.
TEST(FixedScalar, MulShiftRoundMatchesThePortableForm) {
  const int64_t edges[] = {0,
                           1,
                           -1,
                           2,
                           -2,
                           3,
                           -3,
                           INT64_MAX,
                           INT64_MIN,
                           INT64_MAX - 1,
                           INT64_MIN + 1,
                           int64_t{1} << 62,
                           -(int64_t{1} << 62),
                           int64_t{1} << 31,
                           -(int64_t{1} << 31),
                           (int64_t{1} << 30) + 1,
                           -(int64_t{1} << 30) - 1};
  uint64_t x = 0x9E3779B97F4A7C15u;
  const auto next = [&] {  // xorshift64*: any widths, both signs
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    return static_cast<int64_t>(x * 0x2545F4914F6CDD1Du);
  };
  uint64_t differing = 0;
  for (int s = 1; s <= 63; ++s) {
    for (int64_t a : edges)
      for (int64_t b : edges) differing += fx::mul_shift_round(a, b, s) != fx::detail::mul_shift_round_u128(a, b, s);
    for (int i = 0; i < 4000; ++i) {
      const int64_t a = next() >> (i % 64), b = next() >> ((i / 64) % 64);
      differing += fx::mul_shift_round(a, b, s) != fx::detail::mul_shift_round_u128(a, b, s);
    }
  }
  EXPECT_EQ(differing, 0u);
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

// The division-free root must equal the bitwise specification everywhere:
// squares and their neighbours (where an estimate a unit off shows), every
// power-of-two boundary, the top of the range and random values of every
// magnitude. Each result is also checked against the definition
// r^2 <= v < (r + 1)^2 with 128-bit products.
bool fast_root_is_floor_root(uint64_t v) {
  const uint64_t r = fx::isqrt_fast(v);
  const fx::U128 low = fx::mul_u64(r, r), high = fx::mul_u64(r + 1, r + 1);
  const bool low_ok = low.hi == 0 && low.lo <= v;
  const bool high_ok = high.hi > 0 || high.lo > v;
  return low_ok && high_ok && r == fx::isqrt_u64(v);
}

TEST(FixedSqrt, FastRootEqualsTheBitwiseRoot) {
  EXPECT_EQ(fx::isqrt_fast(0), 0u);
  for (uint64_t v = 1; v < (uint64_t{1} << 16); ++v) ASSERT_TRUE(fast_root_is_floor_root(v)) << v;
  for (uint64_t r = 1; r <= 0xFFFFFFFFu; r = r + r / 7 + 1) {
    for (uint64_t d : {uint64_t{0}, uint64_t{1}, uint64_t{2}}) {
      ASSERT_TRUE(fast_root_is_floor_root(r * r - d)) << r;
      if (r * r + d >= r * r) ASSERT_TRUE(fast_root_is_floor_root(r * r + d)) << r;
    }
    ASSERT_TRUE(fast_root_is_floor_root(r * r + 2 * r)) << r;  // (r+1)^2 - 1
  }
  for (int b = 1; b < 64; ++b) {
    const uint64_t p = uint64_t{1} << b;
    for (uint64_t d : {uint64_t{0}, uint64_t{1}}) {
      ASSERT_TRUE(fast_root_is_floor_root(p - d)) << b;
      ASSERT_TRUE(fast_root_is_floor_root(p + d)) << b;
    }
  }
  for (uint64_t d = 0; d < 4096; ++d) ASSERT_TRUE(fast_root_is_floor_root(UINT64_MAX - d)) << d;
  const uint64_t top = uint64_t{0xFFFFFFFFu} * 0xFFFFFFFFu;  // the largest square
  for (uint64_t d = 0; d < 4096; ++d) ASSERT_TRUE(fast_root_is_floor_root(top - 2048 + d)) << d;
  uint64_t state = 0x9E3779B97F4A7C15u;
  for (int i = 0; i < 2000000; ++i) {
    state = state * 6364136223846793005u + 1442695040888963407u;
    const uint64_t v = state >> (state & 63);  // every magnitude
    ASSERT_TRUE(fast_root_is_floor_root(v)) << v;
    const uint64_t r = (state >> 32) | 1;  // a random root: its square and the value below
    ASSERT_TRUE(fast_root_is_floor_root(r * r)) << r;
    ASSERT_TRUE(fast_root_is_floor_root(r * r - 1)) << r;
  }
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
