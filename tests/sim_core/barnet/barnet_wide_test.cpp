// The solve's fast Q2.30 product (mul_l30_round_sat, two plain 64-bit
// products) is the general rounded 64 x 64-bit product shifted by 30
// (mul_shift_round_sat) bit for bit, saturation count included, for every
// factor entry and every solve vector value (|v| <= kVectorLimit, which is
// all the factor and the solve multiply): they switched to it without
// changing any output.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "sim_core/barnet/wide_sat.hpp"

namespace {

void expect_same_l30_product(int32_t l, int64_t v) {
  sinew::fx::Saturation fast_sat, reference_sat;
  const int64_t fast = sinew::barnet::mul_l30_round_sat(l, v, fast_sat);
  const int64_t reference = sinew::barnet::mul_shift_round_sat(l, v, 30, reference_sat);
  ASSERT_EQ(fast, reference) << "l " << l << " v " << v;
  ASSERT_EQ(fast_sat.events, reference_sat.events) << "l " << l << " v " << v;
}

}  // namespace

TEST(BarnetWideProduct, Q30ProductMatchesTheGeneralOne) {
  const int64_t limit = sinew::barnet::kVectorLimit;
  const std::vector<int32_t> ls = {
      0,         1,         -1,    2,      -2, (1 << 29) - 1, 1 << 29, 1 << 30, -(1 << 30), (1 << 30) + 7,
      INT32_MAX, INT32_MIN, 12345, -987654};
  const std::vector<int64_t> vs = {0,
                                   1,
                                   -1,
                                   (int64_t{1} << 29),
                                   -(int64_t{1} << 29),
                                   (int64_t{1} << 30) - 1,
                                   int64_t{1} << 32,
                                   (int64_t{1} << 32) - 1,
                                   -(int64_t{1} << 32),
                                   -(int64_t{1} << 32) + 1,
                                   limit,
                                   -limit,
                                   limit - 1,
                                   -limit + 1,
                                   limit - (int64_t{1} << 32) + 1,
                                   -limit + (int64_t{1} << 32) - 1,
                                   0x123456789ABCDEFLL,
                                   -0x0FEDCBA987654321LL};
  for (int32_t l : ls)
    for (int64_t v : vs) expect_same_l30_product(l, v);
  // Random operands over every magnitude, the half-way cases of the rounding
  // (products with a remainder of exactly 2^29 below the shift) and the
  // extreme factor entries.
  std::mt19937_64 rng(20071207);
  for (int i = 0; i < 2000000; ++i) {
    const int32_t l = static_cast<int32_t>(rng() >> (32 + rng() % 32));
    int64_t v = static_cast<int64_t>(rng() >> (3 + rng() % 61));  // below 2^61
    if (rng() & 1) v = -v;
    expect_same_l30_product(rng() & 1 ? l : -l, v);
    expect_same_l30_product(1, (v & ~((int64_t{1} << 30) - 1)) | (int64_t{1} << 29));  // a remainder of 2^29
    expect_same_l30_product(rng() & 1 ? INT32_MIN : INT32_MAX, v);
  }
}
