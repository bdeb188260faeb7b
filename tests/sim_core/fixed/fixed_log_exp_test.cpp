// log2 / exp2 / pow in fixed point (sim_core/fixed/log_exp.hpp) against
// the C library in floating point. Bounds, from the header's derivation:
//   log2_q30, exp2_fixed: correctly rounded to within 0.5 LSB plus the
//     kernels' error (< 2^-46 of the result: 2^-16 LSB of a Q30 logarithm)
//     and the oracle's own (std::log2 / std::exp2 in double: 1 ulp, 2^-52
//     relative);
//   pow_fixed: the exponent p log2 v is off by at most (|p| + 1) 2^-31, so
//     the result's relative error is at most (|p| + 1) 2^-31 ln 2, plus the
//     output's half LSB.
// The tables are checked against the library too: in long double where it
// has a 64-bit or longer significand (x86-64, aarch64), else in double.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdio>

#include "host_tools/determinism/split_mix.hpp"
#include "sim_core/fixed/log_exp.hpp"

namespace fx = sinew::fx;
using sinew::determinism::SplitMix64;

namespace {

constexpr double kQ30 = 1073741824.0;  // 2^30
constexpr double kLn2 = 0.69314718055994530942;

void log_exp_report(const char* name, double worst, const char* unit) {
  std::printf("numerics: %-22s worst error %.6g %s\n", name, worst, unit);
}

// Relative tolerance of the table check: the oracle's precision plus 1 LSB
// of Q62 (the tables are rounded to it).
constexpr bool kLongOracle = LDBL_MANT_DIG >= 64;
constexpr long double kTableTolerance = kLongOracle ? 0x1p-61L : 0x1p-51L;

}  // namespace

TEST(FixedLogExp, TablesMatchTheLibrary) {
  const long double q62 = 0x1p62L;
  long double worst = 0;
  for (int i = 0; i < fx::kLogExpTableSize; ++i) {
    const long double x = 1.0L + i / 32.0L;
    const long double want[3] = {1.0L / x, std::log2(x), std::exp2(i / 32.0L)};
    const int64_t got[3] = {fx::kReciprocalTableQ62[i], fx::kLog2TableQ62[i], fx::kExp2TableQ62[i]};
    for (int t = 0; t < 3; ++t) {
      const long double err = std::fabs(static_cast<long double>(got[t]) / q62 - want[t]);
      worst = std::max(worst, err);
      EXPECT_LE(err, kTableTolerance * (1 + want[t])) << "table " << t << " entry " << i;
    }
  }
  log_exp_report("log/exp tables", static_cast<double>(worst * q62),
                 kLongOracle ? "LSB of Q62" : "LSB of Q62 (double oracle)");
}

TEST(FixedLogExp, Log2IsCorrectlyRounded) {
  double worst = 0;
  const auto check = [&](uint64_t v, int frac) {
    const double want = (std::log2(static_cast<double>(v)) - frac) * kQ30;
    const double err = std::fabs(static_cast<double>(fx::log2_q30(v, frac)) - want);
    worst = std::max(worst, err);
    // Half an LSB, the kernel (2^-16 LSB) and the oracle (1 ulp of a value
    // below 2^36 in Q30 units: 2^-16 LSB).
    ASSERT_LE(err, 0.5 + 0x1p-10) << "v " << v << " frac " << frac;
  };
  for (uint64_t v = 1; v <= (uint64_t{1} << 20); ++v) check(v, 0);
  SplitMix64 rng(41);
  for (int i = 0; i < 1000000; ++i) {
    const uint64_t v = rng.next() >> (rng.next() % 64);
    if (v != 0) check(v, static_cast<int>(rng.next() % 64));
  }
  for (int k = 0; k < 64; ++k) {  // every power of two and its neighbours
    const uint64_t p = uint64_t{1} << k;
    check(p, 30);
    check(p + 1, 30);
    if (p > 1) check(p - 1, 30);
  }
  check(UINT64_MAX, 62);
  EXPECT_EQ(fx::log2_q30(0, 0), fx::kLog2OfZero);
  EXPECT_EQ(fx::log2_q30(uint64_t{1} << 30, 30), 0);
  log_exp_report("log2_q30", worst, "LSB of Q30");
}

TEST(FixedLogExp, Exp2IsCorrectlyRounded) {
  double worst_lsb = 0, worst_rel = 0;
  const auto check = [&](int64_t x, int frac) {
    const double want = std::exp2(static_cast<double>(x) / kQ30 + frac);
    const int64_t got = fx::exp2_fixed(x, frac);
    if (want >= 0x1p63) {
      ASSERT_EQ(got, INT64_MAX) << "x " << x << " frac " << frac;
      return;
    }
    const double err = std::fabs(static_cast<double>(got) - want);
    if (want < 0x1p30) {
      // The kernel (2^-46 relative) and the double oracle are exact to
      // 2^-16 LSB here.
      worst_lsb = std::max(worst_lsb, err);
      ASSERT_LE(err, 0.5 + 0x1p-10) << "x " << x << " frac " << frac;
    } else {
      // Half an LSB, then the kernel (2^-46), the oracle (2^-52) and the
      // conversion of got to double (2^-53), relative.
      worst_rel = std::max(worst_rel, (err - 0.5) / want);
      ASSERT_LE(err, 0.5 + want * 0x1p-45) << "x " << x << " frac " << frac;
    }
  };
  SplitMix64 rng(42);
  for (int i = 0; i < 1000000; ++i) {
    const int frac = static_cast<int>(rng.next() % 63);
    // Arguments from -70 to +34: every result from underflow to saturation.
    const int64_t x = static_cast<int64_t>(rng.next() % (uint64_t{104} << 30)) - (int64_t{70} << 30);
    check(x, frac);
  }
  for (int64_t n = -66; n <= 34; ++n)
    for (int frac : {0, 20, 30, 62}) {
      check(n << 30, frac);
      check((n << 30) - 1, frac);
      check((n << 30) + 1, frac);
    }
  EXPECT_EQ(fx::exp2_fixed(0, 30), int64_t{1} << 30);
  EXPECT_EQ(fx::exp2_fixed(int64_t{32} << 30, 30), int64_t{1} << 62);
  EXPECT_EQ(fx::exp2_fixed(int64_t{33} << 30, 30), INT64_MAX);
  EXPECT_EQ(fx::exp2_fixed(fx::kLog2OfZero, 62), 0);
  EXPECT_EQ(fx::exp2_fixed(INT64_MIN, 62), 0);
  EXPECT_EQ(fx::exp2_fixed(INT64_MAX, 0), INT64_MAX);
  // Monotone: a larger argument never gives a smaller result.
  for (int i = 0; i < 200000; ++i) {
    const int64_t x = static_cast<int64_t>(rng.next() % (uint64_t{64} << 30)) - (int64_t{40} << 30);
    const int64_t d = static_cast<int64_t>(rng.next() % 4096);
    ASSERT_LE(fx::exp2_fixed(x, 30), fx::exp2_fixed(x + d, 30));
  }
  log_exp_report("exp2_fixed", worst_lsb, "LSB (results < 2^30)");
  log_exp_report("exp2_fixed, large", worst_rel, "relative beyond the half LSB (results >= 2^30)");
}

TEST(FixedLogExp, PowWithinItsExponentBound) {
  // (q)^p for q in (0, 1] (Q30, the superquadric's |x/a|) and p in [1, 16]
  // (Q16.16): the header's bound, (|p| + 1) 2^-31 ln 2 relative plus half
  // an LSB, plus the kernel's 2^-46 and the oracle's 2^-52.
  SplitMix64 rng(43);
  double worst_ratio = 0;  // error / bound
  double worst_rel = 0;
  for (int i = 0; i < 1000000; ++i) {
    const uint64_t q = 1 + rng.next() % (uint64_t{1} << 30);
    const int32_t p = static_cast<int32_t>((int64_t{1} << 16) + static_cast<int64_t>(rng.next() % (15u << 16)) + 1);
    const double pd = p / 65536.0;
    const double want = std::pow(static_cast<double>(q) / kQ30, pd) * kQ30;
    const double err = std::fabs(static_cast<double>(fx::pow_fixed(q, 30, p, 30)) - want);
    const double bound = want * ((pd + 1) * 0x1p-31 * kLn2 + 0x1p-45) + 0.5 + 0x1p-10;
    worst_ratio = std::max(worst_ratio, err / bound);
    if (want > 0x1p20) worst_rel = std::max(worst_rel, (err - 0.5) / want);
    ASSERT_LE(err, bound) << "q " << q << " p " << pd;
  }
  EXPECT_EQ(fx::pow_fixed(0, 30, 3 << 16, 30), 0);
  EXPECT_EQ(fx::pow_fixed(0, 30, 0, 30), int64_t{1} << 30);
  EXPECT_EQ(fx::pow_fixed(0, 30, -(1 << 16), 30), INT64_MAX);
  EXPECT_EQ(fx::pow_fixed(uint64_t{1} << 30, 30, 7 << 16, 30), int64_t{1} << 30);
  log_exp_report("pow_fixed", worst_rel, "relative beyond the half LSB (results > 2^-10)");
  log_exp_report("pow_fixed / bound", worst_ratio, "of the stated bound");
}
