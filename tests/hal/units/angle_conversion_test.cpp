// Binary angles from degrees and radians: wrap instead of clamp, NaN and
// infinities flagged, ties half up, correct rounding for huge inputs (values
// from exact rational / 3000-bit arithmetic), exact round trips.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "expect_conversion.hpp"
#include "hal/units/float_to_fixed.hpp"

namespace sinew::units {
namespace {

using Limits = std::numeric_limits<double>;

constexpr double kHalfStepDeg = 45 * 0x1p-30;  // 360 / 2^33
constexpr uint32_t kQuarter = uint32_t{1} << 30;

std::vector<uint32_t> sample_angles() {
  std::vector<uint32_t> a = {
      0, 1, 0xFFFFFFFFu, kQuarter, 2 * kQuarter, 3 * kQuarter, 2 * kQuarter - 1, 2 * kQuarter + 1};
  std::mt19937_64 rng(21);
  for (int i = 0; i < 100000; ++i) a.push_back(static_cast<uint32_t>(rng()));
  return a;
}

TEST(AngleConversion, ExactDegreesAreOk) {
  EXPECT_TRUE(converts_to(angle_from_degrees(0.0), 0u, kOk));
  EXPECT_TRUE(converts_to(angle_from_degrees(90.0), kQuarter, kOk));
  EXPECT_TRUE(converts_to(angle_from_degrees(-90.0), 3 * kQuarter, kOk));
  EXPECT_TRUE(converts_to(angle_from_degrees(180.0), 2 * kQuarter, kOk));
  EXPECT_TRUE(converts_to(angle_from_degrees(-180.0), 2 * kQuarter, kOk));
  EXPECT_TRUE(converts_to(angle_from_degrees(2 * kHalfStepDeg), 1u, kOk));
}

TEST(AngleConversion, DegreesWrapInsteadOfClamping) {
  EXPECT_TRUE(converts_to(angle_from_degrees(360.0), 0u, kOk));
  EXPECT_TRUE(converts_to(angle_from_degrees(-720.0), 0u, kOk));
  EXPECT_TRUE(converts_to(angle_from_degrees(450.0), kQuarter, kOk));
  EXPECT_TRUE(converts_to(angle_from_degrees(10.0), 119304647u, kRounded));
  EXPECT_TRUE(converts_to(angle_from_degrees(370.0), 119304647u, kRounded));
  EXPECT_TRUE(converts_to(angle_from_degrees(-10.0), 4175662649u, kRounded));
  // Just below a full turn rounds up to it, i.e. to 0.
  EXPECT_TRUE(converts_to(angle_from_degrees(below(360.0)), 0u, kRounded));
  EXPECT_TRUE(converts_to(angle_from_degrees(-below(360.0)), 0u, kRounded));
}

TEST(AngleConversion, HugeDegreesAreReducedExactly) {
  // Expected: round_half_up(x * 2^32 / 360) mod 2^32 in exact rationals.
  EXPECT_TRUE(converts_to(angle_from_degrees(1e300), 0u, kOk));  // a multiple of 360
  EXPECT_TRUE(converts_to(angle_from_degrees(-1e300), 0u, kOk));
  EXPECT_TRUE(converts_to(angle_from_degrees(1e22), 3340530119u, kRounded));
  EXPECT_TRUE(converts_to(angle_from_degrees(Limits::max()), 1527099483u, kRounded));
  EXPECT_TRUE(converts_to(angle_from_degrees(123456789.123), 2256325278u, kRounded));
  EXPECT_TRUE(converts_to(angle_from_degrees(0.1), 1193046u, kRounded));
}

TEST(AngleConversion, DegreeTiesRoundHalfUp) {
  EXPECT_TRUE(converts_to(angle_from_degrees(kHalfStepDeg), 1u, kRounded));
  EXPECT_TRUE(converts_to(angle_from_degrees(-kHalfStepDeg), 0u, kRounded));
  EXPECT_TRUE(converts_to(angle_from_degrees(3 * kHalfStepDeg), 2u, kRounded));
  EXPECT_TRUE(converts_to(angle_from_degrees(-3 * kHalfStepDeg), 0xFFFFFFFFu, kRounded));
  EXPECT_TRUE(converts_to(angle_from_degrees(90.0 + kHalfStepDeg), kQuarter + 1, kRounded));
  EXPECT_TRUE(converts_to(angle_from_degrees(-180.0 - kHalfStepDeg), 2 * kQuarter, kRounded));
  EXPECT_TRUE(converts_to(angle_from_degrees(360.0 - kHalfStepDeg), 0u, kRounded));
  EXPECT_TRUE(converts_to(angle_from_degrees(below(kHalfStepDeg)), 0u, kRounded));
}

TEST(AngleConversion, NotFiniteIsZeroAndFlagged) {
  const double bad[] = {Limits::quiet_NaN(), -Limits::quiet_NaN(), Limits::signaling_NaN(), kInf, -kInf};
  for (double b : bad) {
    EXPECT_TRUE(converts_to(angle_from_degrees(b), 0u, kNotFinite)) << b;
    EXPECT_TRUE(converts_to(angle_from_radians(b), 0u, kNotFinite)) << b;
  }
}

TEST(AngleConversion, ZerosAndDenormals) {
  EXPECT_TRUE(converts_to(angle_from_degrees(-0.0), 0u, kOk));
  EXPECT_TRUE(converts_to(angle_from_radians(0.0), 0u, kOk));
  EXPECT_TRUE(converts_to(angle_from_radians(-0.0), 0u, kOk));
  const double tiny[] = {Limits::denorm_min(), Limits::min() / 7, Limits::min(), 1e-200};
  for (double t : tiny) {
    EXPECT_TRUE(converts_to(angle_from_degrees(t), 0u, kRounded)) << t;
    EXPECT_TRUE(converts_to(angle_from_degrees(-t), 0u, kRounded)) << t;
    EXPECT_TRUE(converts_to(angle_from_radians(t), 0u, kRounded)) << t;
    EXPECT_TRUE(converts_to(angle_from_radians(-t), 0u, kRounded)) << t;
  }
}

TEST(AngleConversion, RadiansAreCorrectlyRounded) {
  // Expected values from 3000-bit arithmetic: round(x * 2^31 / pi) mod 2^32.
  struct Case {
    double rad;
    uint32_t angle;
  };
  const Case cases[] = {
      {1.0, 0x28BE60DCu},
      {-1.0, 0xD7419F24u},
      {std::numbers::pi, 0x80000000u},
      {-std::numbers::pi, 0x80000000u},
      {2 * std::numbers::pi, 0u},
      {1e-9, 1u},
      {0x1p-32, 0u},
      {1e6, 0xF16E7870u},
      {-1e6, 0x0E918790u},
      {1e22, 0xD66F29F0u},
      {1e300, 0xA705623Cu},
      {-1e300, 0x58FA9DC4u},
      {Limits::max(), 0x7FCC3EA6u},
      // 6381956970095103 * 2^797 lies within 2^-60.9 of a multiple of pi/2
      // (the closest double): a quarter-turn multiple.
      {0x1.6ac5b262ca1ffp+849, 0x40000000u},
      {-0x1.6ac5b262ca1ffp+849, 0xC0000000u},
      // The same mantissa at 2^766 sits 2^-62.5 step above a tie.
      {0x1.6ac5b262ca1ffp+818, 0xAF0F56DBu},
      {-0x1.6ac5b262ca1ffp+818, 0x50F0A925u},
  };
  for (const Case& c : cases) EXPECT_TRUE(converts_to(angle_from_radians(c.rad), c.angle, kRounded)) << c.rad;
}

TEST(AngleConversion, RadiansMatchLongDoubleAwayFromTies) {
  std::mt19937_64 rng(22);
  std::uniform_real_distribution<double> rad(-100.0, 100.0);
  for (int i = 0; i < 200000; ++i) {
    const double x = rad(rng);
    const long double steps = static_cast<long double>(x) * 2147483648.0L / std::numbers::pi_v<long double>;
    const long double whole = std::floor(steps);
    if (std::fabs(steps - whole - 0.5L) < 1e-3L) continue;  // too close to a tie for the oracle
    const auto want = static_cast<uint32_t>(static_cast<int64_t>(whole) + (steps - whole > 0.5L ? 1 : 0));
    ASSERT_TRUE(converts_to(angle_from_radians(x), want, kRounded)) << x;
  }
}

TEST(AngleConversion, RoundTripsAreExact) {
  for (uint32_t a : sample_angles()) {
    ASSERT_TRUE(converts_to(angle_from_degrees(angle_to_degrees(a)), a, kOk));
    // Every nonzero radian value is inexact, but the nearest angle is `a`.
    ASSERT_TRUE(converts_to(angle_from_radians(angle_to_radians(a)), a, a == 0 ? kOk : kRounded));
  }
}

TEST(AngleConversion, ReverseIsTheSignedView) {
  EXPECT_EQ(angle_to_degrees(kQuarter), 90.0);
  EXPECT_EQ(angle_to_degrees(3 * kQuarter), -90.0);
  EXPECT_EQ(angle_to_degrees(2 * kQuarter), -180.0);
  EXPECT_EQ(angle_to_degrees(2 * kQuarter - 1), 180.0 - 2 * kHalfStepDeg);
  EXPECT_EQ(angle_to_radians(2 * kQuarter), -std::numbers::pi);
  EXPECT_NEAR(angle_to_radians(kQuarter), std::numbers::pi / 2, 1e-16);
}

// Ranges and limits need (-180, 180]: +180 saturates instead of wrapping to
// -180, whichever turn it comes from; -180 and everything else is the int32
// view of angle_from_degrees.
TEST(AngleConversion, SignedDegreesKeepPlusHalfTurnAboveMinusHalfTurn) {
  EXPECT_TRUE(converts_to(signed_angle_from_degrees(180.0), INT32_MAX, kClamped));
  EXPECT_TRUE(converts_to(signed_angle_from_degrees(540.0), INT32_MAX, kClamped));
  EXPECT_TRUE(converts_to(signed_angle_from_degrees(std::nextafter(180.0, 0.0)), INT32_MAX, kClamped));
  EXPECT_TRUE(converts_to(signed_angle_from_degrees(-180.0), INT32_MIN, kOk));
  EXPECT_TRUE(converts_to(signed_angle_from_degrees(-540.0), INT32_MIN, kOk));
  EXPECT_TRUE(converts_to(signed_angle_from_degrees(90.0), int32_t{1} << 30, kOk));
  EXPECT_TRUE(converts_to(signed_angle_from_degrees(270.0), -(int32_t{1} << 30), kOk));
  EXPECT_TRUE(converts_to(signed_angle_from_degrees(Limits::quiet_NaN()), 0, kNotFinite));
  EXPECT_TRUE(converts_to(signed_angle_from_degrees(Limits::infinity()), 0, kNotFinite));
  for (const uint32_t a : sample_angles()) {
    if (a == 0x80000000u) continue;
    EXPECT_TRUE(converts_to(signed_angle_from_degrees(angle_to_degrees(a)), static_cast<int32_t>(a), kOk)) << a;
  }
}

}  // namespace
}  // namespace sinew::units
