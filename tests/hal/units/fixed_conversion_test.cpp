// Unit (Q2.30), Lin (Q8.24) and Len (Q12.20 with a length exponent) from
// doubles: each bad input class of the header's table, the range edges, the
// ties, and exact round trips.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "expect_conversion.hpp"
#include "hal/units/float_to_fixed.hpp"

namespace sinew::units {
namespace {

using Limits = std::numeric_limits<double>;

const double kNaN = Limits::quiet_NaN();

// Independent oracle: round half up of x * 2^frac_bits in plain double
// arithmetic (the scaling, floor and the fraction are all exact), for x whose
// scaled value stays below 2^62.
int64_t oracle_round(double x, int frac_bits) {
  const double scaled = std::ldexp(x, frac_bits);
  const double whole = std::floor(scaled);
  return static_cast<int64_t>(whole) + (scaled - whole >= 0.5 ? 1 : 0);
}

TEST(FixedConversion, ExactValuesAreOk) {
  EXPECT_TRUE(converts_to(to_unit(1.0), int32_t{1} << 30, kOk));
  EXPECT_TRUE(converts_to(to_unit(-1.0), -(int32_t{1} << 30), kOk));
  EXPECT_TRUE(converts_to(to_unit(-2.0), INT32_MIN, kOk));
  EXPECT_TRUE(converts_to(to_unit(2.0 - 0x1p-30), INT32_MAX, kOk));
  EXPECT_TRUE(converts_to(to_unit(0x1p-30), 1, kOk));
  EXPECT_TRUE(converts_to(to_lin(-128.0), INT32_MIN, kOk));
  EXPECT_TRUE(converts_to(to_lin(128.0 - 0x1p-24), INT32_MAX, kOk));
  EXPECT_TRUE(converts_to(to_lin(0.01171875), 196608, kOk));  // 3/256
  EXPECT_TRUE(converts_to(to_len(1.0, 0), int32_t{1} << 20, kOk));
  EXPECT_TRUE(converts_to(to_len(1.0, -2), int32_t{1} << 22, kOk));  // rig unit 0.25: 4 units
  EXPECT_TRUE(converts_to(to_len(-2048.0, 0), INT32_MIN, kOk));
}

TEST(FixedConversion, SignedZerosAreExactZero) {
  EXPECT_TRUE(converts_to(to_unit(0.0), 0, kOk));
  EXPECT_TRUE(converts_to(to_unit(-0.0), 0, kOk));
  EXPECT_TRUE(converts_to(to_lin(-0.0), 0, kOk));
  EXPECT_TRUE(converts_to(to_len(-0.0, 0), 0, kOk));
  EXPECT_TRUE(converts_to(to_len(-0.0, INT32_MIN), 0, kOk));
  EXPECT_TRUE(converts_to(to_len(0.0, INT32_MAX), 0, kOk));
}

TEST(FixedConversion, NaNIsZeroAndFlagged) {
  const double nans[] = {kNaN, -kNaN, Limits::signaling_NaN(), std::nan("0x123")};
  for (double n : nans) {
    EXPECT_TRUE(converts_to(to_unit(n), 0, kNotFinite));
    EXPECT_TRUE(converts_to(to_lin(n), 0, kNotFinite));
    EXPECT_TRUE(converts_to(to_len(n, 0), 0, kNotFinite));
    EXPECT_TRUE(converts_to(to_len(n, -1000), 0, kNotFinite));
  }
}

TEST(FixedConversion, InfinitiesSaturateAndAreFlagged) {
  const ConversionFlags f = kNotFinite | kClamped;
  EXPECT_TRUE(converts_to(to_unit(kInf), INT32_MAX, f));
  EXPECT_TRUE(converts_to(to_unit(-kInf), INT32_MIN, f));
  EXPECT_TRUE(converts_to(to_lin(kInf), INT32_MAX, f));
  EXPECT_TRUE(converts_to(to_lin(-kInf), INT32_MIN, f));
  EXPECT_TRUE(converts_to(to_len(kInf, 5), INT32_MAX, f));
  EXPECT_TRUE(converts_to(to_len(-kInf, INT32_MAX), INT32_MIN, f));
}

TEST(FixedConversion, JustAboveRangeClamps) {
  // 2 - 2^-31 is the tie between INT32_MAX and 2^31: half up goes out of range.
  EXPECT_TRUE(converts_to(to_unit(2.0), INT32_MAX, kClamped));
  EXPECT_TRUE(converts_to(to_unit(below(2.0)), INT32_MAX, kClamped));
  EXPECT_TRUE(converts_to(to_unit(2.0 - 0x1p-31), INT32_MAX, kClamped));
  EXPECT_TRUE(converts_to(to_unit(below(2.0 - 0x1p-31)), INT32_MAX, kRounded));
  EXPECT_TRUE(converts_to(to_lin(128.0), INT32_MAX, kClamped));
  EXPECT_TRUE(converts_to(to_lin(128.0 - 0x1p-25), INT32_MAX, kClamped));
  EXPECT_TRUE(converts_to(to_lin(below(128.0 - 0x1p-25)), INT32_MAX, kRounded));
  EXPECT_TRUE(converts_to(to_len(2048.0, 0), INT32_MAX, kClamped));
  EXPECT_TRUE(converts_to(to_len(4096.0, 1), INT32_MAX, kClamped));  // 2048 rig units
  EXPECT_TRUE(converts_to(to_len(4096.0 - 0x1p-19, 1), INT32_MAX, kOk));
}

TEST(FixedConversion, JustBelowRangeRoundsThenClamps) {
  // -2 - 2^-31 is the tie between INT32_MIN - 1 and INT32_MIN: half up stays in.
  EXPECT_TRUE(converts_to(to_unit(below(-2.0)), INT32_MIN, kRounded));
  EXPECT_TRUE(converts_to(to_unit(-2.0 - 0x1p-31), INT32_MIN, kRounded));
  EXPECT_TRUE(converts_to(to_unit(below(-2.0 - 0x1p-31)), INT32_MIN, kClamped));
  EXPECT_TRUE(converts_to(to_unit(-2.0 - 0x1p-30), INT32_MIN, kClamped));
  EXPECT_TRUE(converts_to(to_lin(-128.0 - 0x1p-25), INT32_MIN, kRounded));
  EXPECT_TRUE(converts_to(to_lin(below(-128.0 - 0x1p-25)), INT32_MIN, kClamped));
  EXPECT_TRUE(converts_to(to_len(-2048.0 - 0x1p-21, 0), INT32_MIN, kRounded));
  EXPECT_TRUE(converts_to(to_len(below(-2048.0 - 0x1p-21), 0), INT32_MIN, kClamped));
}

TEST(FixedConversion, HugeValuesClamp) {
  const double huge[] = {3.0, 1e10, 1e300, Limits::max(), 0x1p62, 0x1p63, 0x1p64};
  for (double h : huge) {
    EXPECT_TRUE(converts_to(to_unit(h), INT32_MAX, kClamped)) << h;
    EXPECT_TRUE(converts_to(to_unit(-h), INT32_MIN, kClamped)) << h;
    EXPECT_TRUE(converts_to(to_len(h, -11), INT32_MAX, kClamped)) << h;  // >= 6144 rig units
    EXPECT_TRUE(converts_to(to_len(-h, -11), INT32_MIN, kClamped)) << h;
  }
  // An exponent that makes any nonzero value huge, or any value tiny.
  EXPECT_TRUE(converts_to(to_len(Limits::denorm_min(), INT32_MIN), INT32_MAX, kClamped));
  EXPECT_TRUE(converts_to(to_len(-1.0, -12), INT32_MIN, kClamped));  // 4096 rig units
  EXPECT_TRUE(converts_to(to_len(Limits::max(), INT32_MAX), 0, kRounded));
  EXPECT_TRUE(converts_to(to_len(-Limits::max(), 2000), 0, kRounded));
}

TEST(FixedConversion, DenormalsRoundToZero) {
  const double tiny[] = {Limits::denorm_min(), 0x1p-1050, Limits::min() / 3, Limits::min(), 1e-300};
  for (double t : tiny) {
    EXPECT_TRUE(converts_to(to_unit(t), 0, kRounded)) << t;
    EXPECT_TRUE(converts_to(to_unit(-t), 0, kRounded)) << t;
    EXPECT_TRUE(converts_to(to_lin(-t), 0, kRounded)) << t;
    EXPECT_TRUE(converts_to(to_len(t, 0), 0, kRounded)) << t;
  }
  // With a small enough rig unit a denormal is representable, ties included:
  // 2^-1074 at exponent -1054 is exactly one LSB, at -1053 exactly half of one.
  const double d = Limits::denorm_min();
  EXPECT_TRUE(converts_to(to_len(d, -1054), 1, kOk));
  EXPECT_TRUE(converts_to(to_len(-d, -1054), -1, kOk));
  EXPECT_TRUE(converts_to(to_len(d, -1053), 1, kRounded));
  EXPECT_TRUE(converts_to(to_len(-d, -1053), 0, kRounded));
  EXPECT_TRUE(converts_to(to_len(3 * d, -1053), 2, kRounded));
  EXPECT_TRUE(converts_to(to_len(-3 * d, -1053), -1, kRounded));
}

TEST(FixedConversion, TiesRoundHalfUp) {
  const double lsb = 0x1p-30;
  EXPECT_TRUE(converts_to(to_unit(0.5 * lsb), 1, kRounded));
  EXPECT_TRUE(converts_to(to_unit(-0.5 * lsb), 0, kRounded));
  EXPECT_TRUE(converts_to(to_unit(1.5 * lsb), 2, kRounded));
  EXPECT_TRUE(converts_to(to_unit(-1.5 * lsb), -1, kRounded));
  EXPECT_TRUE(converts_to(to_unit(2.5 * lsb), 3, kRounded));
  EXPECT_TRUE(converts_to(to_unit(-2.5 * lsb), -2, kRounded));
  EXPECT_TRUE(converts_to(to_unit(1.0 + 0.5 * lsb), (int32_t{1} << 30) + 1, kRounded));
  EXPECT_TRUE(converts_to(to_unit(-1.0 - 0.5 * lsb), -(int32_t{1} << 30), kRounded));
  // One ulp either side of a tie goes to the nearer value.
  EXPECT_TRUE(converts_to(to_unit(below(0.5 * lsb)), 0, kRounded));
  EXPECT_TRUE(converts_to(to_unit(above(-0.5 * lsb)), 0, kRounded));
  EXPECT_TRUE(converts_to(to_unit(below(-0.5 * lsb)), -1, kRounded));
  EXPECT_TRUE(converts_to(to_lin(0x1p-25), 1, kRounded));
  EXPECT_TRUE(converts_to(to_lin(-0x1p-25), 0, kRounded));
  EXPECT_TRUE(converts_to(to_len(0x1p-21, 0), 1, kRounded));
  EXPECT_TRUE(converts_to(to_len(-0x1p-21, 0), 0, kRounded));
  EXPECT_TRUE(converts_to(to_len(-0x1p-18, 3), 0, kRounded));  // -0.5 LSB at 8 units per rig unit
}

TEST(FixedConversion, MatchesRoundingOracle) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> mantissa(-2.0, 2.0);
  std::uniform_int_distribution<int> scale(-40, 0);
  for (int i = 0; i < 200000; ++i) {
    const double x = std::ldexp(mantissa(rng), scale(rng));
    const int64_t want = oracle_round(x, 30);
    const FixedResult r = to_unit(x);
    if (want > INT32_MAX) {
      ASSERT_TRUE(converts_to(r, INT32_MAX, kClamped)) << x;
    } else {
      ASSERT_TRUE(
          converts_to(r, static_cast<int32_t>(want), std::ldexp(x, 30) == static_cast<double>(want) ? kOk : kRounded))
          << x;
    }
  }
}

TEST(FixedConversion, RepresentableValuesRoundTripExactly) {
  std::mt19937_64 rng(12);
  std::vector<int32_t> values = {0, 1, -1, INT32_MAX, INT32_MIN, INT32_MAX - 1, INT32_MIN + 1, 1 << 30, -(1 << 30)};
  for (int i = 0; i < 100000; ++i) values.push_back(static_cast<int32_t>(static_cast<uint32_t>(rng())));
  for (int32_t v : values) {
    ASSERT_TRUE(converts_to(to_unit(unit_to_double(v)), v, kOk));
    ASSERT_TRUE(converts_to(to_lin(lin_to_double(v)), v, kOk));
    for (int32_t e : {-60, -12, -7, -1, 0, 1, 3, 10, 40, 900, -900}) {
      ASSERT_TRUE(converts_to(to_len(len_to_double(v, e), e), v, kOk)) << e;
    }
  }
}

TEST(FixedConversion, ReverseIsExactScaling) {
  EXPECT_EQ(unit_to_double(INT32_MIN), -2.0);
  EXPECT_EQ(unit_to_double(INT32_MAX), 2.0 - 0x1p-30);
  EXPECT_EQ(lin_to_double(1 << 24), 1.0);
  EXPECT_EQ(len_to_double(1 << 20, 0), 1.0);
  EXPECT_EQ(len_to_double(1 << 20, -10), 0x1p-10);  // one rig unit of 2^-10 m
  EXPECT_EQ(len_to_double(3, 1042), 0x1.8p1023);
  // Beyond double's range the reverse saturates to 0 or inf.
  EXPECT_EQ(len_to_double(1, INT32_MIN), 0.0);
  EXPECT_EQ(len_to_double(1, INT32_MAX), kInf);
  EXPECT_EQ(len_to_double(-1, INT32_MAX), -kInf);
}

// The general form: the named formats are to_fixed with their fraction bits,
// and any other Q format (force Q15.16, a negative scale) follows one rule.
TEST(FixedConversion, AnyFormatFollowsTheSameRule) {
  for (const double x : {0.0, 1.5, -1.5, 0.1, -0.1, 1e-12, 3.0, -2.0, 1e30, -1e30}) {
    const FixedResult u = to_unit(x), f = to_fixed(x, 30);
    EXPECT_EQ(u.value, f.value) << x;
    EXPECT_EQ(u.flags, f.flags) << x;
    const FixedResult l = to_lin(x), g = to_fixed(x, 24);
    EXPECT_EQ(l.value, g.value) << x;
    EXPECT_EQ(l.flags, g.flags) << x;
  }
  EXPECT_TRUE(converts_to(to_fixed(1.5, 16), 98304, kOk));
  EXPECT_TRUE(converts_to(to_fixed(-0.5 / 65536.0, 16), 0, kRounded));  // tie: towards +infinity
  EXPECT_TRUE(converts_to(to_fixed(0.5 / 65536.0, 16), 1, kRounded));
  EXPECT_TRUE(converts_to(to_fixed(32768.0, 16), INT32_MAX, kClamped));
  EXPECT_TRUE(converts_to(to_fixed(1024.0, -4), 64, kOk));
  EXPECT_TRUE(converts_to(to_fixed(Limits::quiet_NaN(), 16), 0, kNotFinite));
}

}  // namespace
}  // namespace sinew::units
