// The smoothing kernels of sim_core/sph/sph_kernels.hpp against their closed
// forms (Mueller, Charypar and Gross 2003, the paper's [37]; normalised as
// the header documents) evaluated in double, over every q = r / h in [0, 1).
// Each bound is derived from the Q format and the table construction, not
// measured: rounding of the stored words, the floor of the integer square
// root, and the chord error of linear interpolation over a table step
// (|f - chord| <= step^2 / 8 max |f''| over the step).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "sim_core/sph/sph_kernels.hpp"

namespace {

namespace sph = sinew::sph;

constexpr double kTwo30 = 1073741824.0;
constexpr double kTwo24 = 16777216.0;
constexpr double kTableStep = 1.0 / 1024.0;  // s step of the 1025-entry tables (kTableBits = 10)
constexpr uint32_t kSampleStride = 997;      // prime: the samples fall on every offset within a step

double s_of_word(uint32_t s) { return static_cast<double>(s) / kTwo30; }

// Left end of the table step holding s (the largest |f''| of both kernels
// below lies there: each |f''| decreases with s).
double step_start(double s) { return std::floor(s / kTableStep) * kTableStep; }

}  // namespace

TEST(SphKernels, Poly6MatchesClosedForm) {
  // (1 - s)^3, s = q^2: 1 - s is exact; each of the two products rounds
  // once to Q30 (0.5 LSB), the first one's error multiplied by 1 - s <= 1.
  const double bound_lsb = 0.5 + 0.5;
  double worst = 0;
  for (uint32_t s = 0; s < (uint32_t{1} << 30); s += kSampleStride) {
    const double t = 1.0 - s_of_word(s);
    const double err = std::abs(static_cast<double>(sph::poly6(s)) - t * t * t * kTwo30);
    worst = std::max(worst, err);
    ASSERT_LE(err, bound_lsb) << "s word " << s;
  }
  EXPECT_EQ(sph::poly6(0), int32_t{1} << 30) << "a particle alone has density 1";
  EXPECT_LE(sph::poly6((uint32_t{1} << 30) - 1), 1) << "poly6 vanishes at the kernel's edge";
  std::printf("poly6: worst %.3f LSB of Q2.30 (bound %.1f)\n", worst, bound_lsb);
}

TEST(SphKernels, SpikyGradientFactorMatchesClosedForm) {
  // (1 - q)^2 / q = 1/sqrt(s) - 2 + sqrt(s); f''(s) = 3/4 s^-5/2 - 1/4 s^-3/2.
  // Table word: q from the floored integer sqrt (q off by < 2^-30, times
  // |d/dq| = |1 - 1/q^2| < 1/q^2), the integer division (< 2^-30) and the
  // rounding to Q24 (0.5 LSB); interpolation rounds once more (0.5 LSB).
  // Below the first step q is clamped to 1/32 (documented): there the
  // factor is the closed form at q = 1/32.
  double worst_ratio = 0;
  for (uint32_t s = 0; s < (uint32_t{1} << 30); s += kSampleStride) {
    const double sd = s_of_word(s);
    const double clamped = std::max(sd, kTableStep);
    const double q = std::sqrt(clamped);
    const double want = (1 - q) * (1 - q) / q * kTwo24;
    const double left = std::max(step_start(sd), kTableStep);
    const double f2 = 0.75 * std::pow(left, -2.5) + 0.25 * std::pow(left, -1.5);
    const double chord = sd < kTableStep ? 0.0 : kTableStep * kTableStep / 8 * f2 * kTwo24;
    const double word = (1.0 / left + 1.0) / kTwo30 * kTwo24 + 1.0 / kTwo30 * kTwo24 + 0.5;
    const double bound = chord + word + 0.5;
    const double err = std::abs(static_cast<double>(sph::spiky_factor(s)) - want);
    worst_ratio = std::max(worst_ratio, err / bound);
    ASSERT_LE(err, bound) << "s word " << s << " q " << q;
  }
  std::printf("spiky gradient factor: worst error %.3f of its derived bound\n", worst_ratio);
}

TEST(SphKernels, ViscosityLaplacianFactorMatchesClosedForm) {
  // 1 - q = 1 - sqrt(s); f''(s) = 1/4 s^-3/2. On the first step the chord
  // error of sqrt over [0, step] is at most sqrt(step) / 4 (at s = step / 4).
  // Table word: the floored sqrt, < 1 LSB; interpolation rounds 0.5 LSB.
  double worst_ratio = 0;
  for (uint32_t s = 0; s < (uint32_t{1} << 30); s += kSampleStride) {
    const double sd = s_of_word(s);
    const double want = (1 - std::sqrt(sd)) * kTwo30;
    const double left = step_start(sd);
    const double chord = left == 0 ? std::sqrt(kTableStep) / 4 * kTwo30
                                   : kTableStep * kTableStep / 8 * 0.25 * std::pow(left, -1.5) * kTwo30;
    const double bound = chord + 1.0 + 0.5;
    const double err = std::abs(static_cast<double>(sph::viscosity_factor(s)) - want);
    worst_ratio = std::max(worst_ratio, err / bound);
    ASSERT_LE(err, bound) << "s word " << s;
  }
  std::printf("viscosity laplacian factor: worst error %.3f of its derived bound\n", worst_ratio);
}

TEST(SphKernels, CombinedLookupGivesTheSameWords) {
  for (uint32_t s = 0; s < (uint32_t{1} << 30); s += 7919) {
    int32_t spiky = 0, viscosity = 0;
    sph::kernel_factors(s, &spiky, &viscosity);
    ASSERT_EQ(spiky, sph::spiky_factor(s));
    ASSERT_EQ(viscosity, sph::viscosity_factor(s));
  }
}

TEST(SphKernels, PairGeometryIsTheNormalisedOffset) {
  // d = (a - b) / h in Q30 from round(2^50 / h): component k is off by at
  // most e_k = 0.5 LSB (its rounding) + |a_k - b_k| x 0.5 / 2^20 (the
  // rounded reciprocal); s = |d|^2 then by sum 2 |d_k| e_k + e_k^2 / 2^30
  // plus its own rounding (0.5).
  const int32_t h = 3 << 20;  // 3 rig units in Len
  const sph::InvH ih = sph::make_inv_h(h);
  uint64_t state = 0x9e3779b97f4a7c15ull;
  int inside = 0;
  for (int k = 0; k < 20000; ++k) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    const auto component = [&state](int shift) {
      return static_cast<int32_t>(static_cast<int64_t>((state >> shift) & 0x7fffff) - 0x400000);
    };
    const sinew::fx::Vec3 a{component(0), component(21), component(41)};
    const sinew::fx::Vec3 b{0, 0, 0};
    sph::PairGeometry g;
    const double d[3] = {static_cast<double>(a.x) / h, static_cast<double>(a.y) / h, static_cast<double>(a.z) / h};
    const double s = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const bool in = sph::pair_geometry(a, b, ih, &g);
    if (s < 1 - 1e-7) {
      ASSERT_TRUE(in) << "a point inside the kernel was rejected";
    } else if (s > 1 + 1e-7) {
      ASSERT_FALSE(in) << "a point outside the kernel was accepted";
    }
    if (!in) continue;
    ++inside;
    const int32_t got[3] = {g.d.x, g.d.y, g.d.z};
    const int32_t offset[3] = {a.x, a.y, a.z};
    double s_bound = 0.5;
    for (int c = 0; c < 3; ++c) {
      const double e = 0.5 + std::abs(static_cast<double>(offset[c])) * 0.5 / 1048576.0;
      ASSERT_LE(std::abs(got[c] - d[c] * kTwo30), e);
      s_bound += 2 * std::abs(d[c]) * e + e * e / kTwo30;
    }
    ASSERT_LE(std::abs(static_cast<double>(g.s) - s * kTwo30), s_bound);
  }
  EXPECT_GT(inside, 1000);
}
