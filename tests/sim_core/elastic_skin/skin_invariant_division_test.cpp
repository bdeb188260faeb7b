// The skin's division by a tick-invariant divisor (LEMAN §3 integrator:
// x += v' / H, the implicit-dashpot denominator, the anchors' path across a
// tick) must be fx::div_round bit for bit, or the dynamic skin's outputs
// would change with the speed-up. Oracle: fx::div_round itself, on edge
// values and on a deterministic pseudo-random sweep.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "sim_core/elastic_skin/invariant_division.hpp"
#include "sim_core/fixed/scalar.hpp"

namespace {

namespace es = sinew::elastic_skin;

uint64_t invariant_division_next(uint64_t* state) {  // splitmix64
  uint64_t z = (*state += 0x9E3779B97F4A7C15u);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
  return z ^ (z >> 31);
}

TEST(SkinInvariantDivision, MatchesDivRoundOnEdgeValues) {
  const std::vector<int64_t> divisors = {1,
                                         2,
                                         3,
                                         4,
                                         7,
                                         64,
                                         4000,
                                         400000,
                                         6400000,
                                         1 << 30,
                                         (1ll << 32) + 1,
                                         1ll << 40,
                                         INT64_MAX / 3,
                                         INT64_MAX - 1,
                                         INT64_MAX};
  std::vector<int64_t> numerators = {0, 1, -1, 2, -2, INT64_MAX, INT64_MIN, INT64_MIN + 1, INT64_MAX - 1};
  for (int64_t d : divisors)
    for (int64_t k : {-2, -1, 0, 1, 2})
      for (int64_t m : {int64_t{1}, int64_t{3}, int64_t{1} << 20}) {
        // Around multiples and half-multiples of d, where the rounding turns.
        if (d > INT64_MAX / 4 && m > 1) continue;
        const int64_t base = d * m;
        // Saturating: base may be INT64_MAX itself.
        numerators.push_back(sinew::fx::add_sat_i64(base, k));
        numerators.push_back(sinew::fx::add_sat_i64(-base, k));
        numerators.push_back(sinew::fx::add_sat_i64(base / 2, k));
        numerators.push_back(sinew::fx::add_sat_i64(-(base / 2), k));
      }
  int checked = 0;
  for (int64_t d : divisors) {
    const es::InvariantDivisor by = es::invariant_divisor(d);
    for (int64_t n : numerators) {
      ASSERT_EQ(es::div_round_by(n, by), sinew::fx::div_round(n, d)) << n << " / " << d;
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
}

TEST(SkinInvariantDivision, MatchesDivRoundOnRandomValues) {
  uint64_t state = 12345;
  for (int i = 0; i < 200000; ++i) {
    const uint64_t r = invariant_division_next(&state);
    // Divisors of every width from 1 to 63 bits, numerators of every width.
    const int64_t d = static_cast<int64_t>((r >> (1 + i % 63)) | 1u) >> (i % 3 == 0 ? 0 : 1);
    if (d <= 0) continue;
    const int64_t n = static_cast<int64_t>(invariant_division_next(&state)) >> (i % 64);
    ASSERT_EQ(es::div_round_by(n, es::invariant_divisor(d)), sinew::fx::div_round(n, d)) << n << " / " << d;
  }
}

}  // namespace
