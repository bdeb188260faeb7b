// round_shift and div_round are total over int64 (docs/numerics.md,
// "Rounding and overflow"): inside their former preconditions they give the
// same bits as the former formulas, (v + 2^(s-1)) >> s and
// floor((2n + d) / 2d), so no golden hash moves; outside them (saturated
// sums, quotients of products near 2^63) they round without overflowing.
#include <gtest/gtest.h>

#include <climits>
#include <random>

#include "sim_core/fixed/scalar.hpp"

namespace fx = sinew::fx;

namespace {

int64_t former_round_shift(int64_t v, int s) { return (v + (int64_t{1} << (s - 1))) >> s; }

int64_t former_div_round(int64_t n, int64_t d) {
  if (d == 0) return 0;
  if (d < 0) {
    n = -n;
    d = -d;
  }
  return fx::floor_div(2 * n + d, 2 * d);
}

}  // namespace

TEST(FixedTotalRounding, SameBitsAsTheFormerFormulasInsideTheirDomain) {
  std::mt19937_64 rng(20261124);
  for (int i = 0; i < 400000; ++i) {
    const int bits = static_cast<int>(rng() % 62) + 1;
    const int64_t v = static_cast<int64_t>(rng() >> (64 - bits)) * ((rng() & 1) ? 1 : -1);
    const int s = static_cast<int>(rng() % 62) + 1;
    ASSERT_EQ(fx::round_shift(v, s), former_round_shift(v, s)) << v << " >> " << s;
    const int dbits = static_cast<int>(rng() % 61) + 1;
    int64_t d = static_cast<int64_t>(rng() >> (64 - dbits)) * ((rng() & 1) ? 1 : -1);
    if (i % 7 == 0) d = (rng() & 1) ? 2 : -2;  // ties
    const int64_t n = v / 2;                   // the former formula formed 2n + d
    ASSERT_EQ(fx::div_round(n, d), former_div_round(n, d)) << n << " / " << d;
  }
  for (int64_t n = -40; n <= 40; ++n)
    for (int64_t d = -9; d <= 9; ++d) ASSERT_EQ(fx::div_round(n, d), former_div_round(n, d)) << n << " / " << d;
}

TEST(FixedTotalRounding, ExtremesRoundWithoutOverflow) {
  EXPECT_EQ(fx::round_shift(INT64_MAX, 30), int64_t{1} << 33);
  EXPECT_EQ(fx::round_shift(INT64_MIN, 30), -(int64_t{1} << 33));
  EXPECT_EQ(fx::round_shift(INT64_MAX, 1), int64_t{1} << 62);
  EXPECT_EQ(fx::div_round(INT64_MAX, 2), int64_t{1} << 62);  // 2^62 - 0.5 rounds up
  EXPECT_EQ(fx::div_round(INT64_MIN, 2), -(int64_t{1} << 62));
  EXPECT_EQ(fx::div_round(INT64_MIN, -1), INT64_MAX);  // the one quotient beyond int64 saturates
  EXPECT_EQ(fx::div_round(INT64_MAX, -1), -INT64_MAX);
  EXPECT_EQ(fx::div_round(INT64_MIN, INT64_MAX), -1);
  EXPECT_EQ(fx::div_round(INT64_MAX, INT64_MIN), -1);     // -0.99...: nearest is -1
  EXPECT_EQ(fx::div_round(INT64_MIN / 2, INT64_MIN), 1);  // 0.5 rounds up
  EXPECT_EQ(fx::div_round(int64_t{1} << 62, 3), ((int64_t{1} << 62) + 1) / 3);
  EXPECT_EQ(fx::div_round(-(int64_t{1} << 62) - 3, 2), -(int64_t{1} << 61) - 1);  // -x.5 -> toward +inf
}
