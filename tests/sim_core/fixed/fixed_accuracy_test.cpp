// Accuracy of sim_core/fixed against a double-precision oracle. Each test
// prints its measured worst case ("numerics: ...") — the figures in
// docs/numerics.md — and fails if it exceeds the published bound.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "host_tools/determinism/split_mix.hpp"
#include "sim_core/fixed/mat34.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "sim_core/fixed/trig.hpp"

namespace fx = sinew::fx;
using sinew::determinism::SplitMix64;

namespace {
constexpr double kTwoPi = 6.283185307179586476925286766559;
constexpr double kUnit = 1073741824.0;  // 2^30

double angle_rad(fx::Angle a) { return static_cast<double>(a) * kTwoPi / 4294967296.0; }

void report(const char* name, double worst, const char* unit) {
  std::printf("numerics: %-22s worst error %.3f %s\n", name, worst, unit);
}
}  // namespace

TEST(FixedAccuracy, IsqrtIsExactFloor) {
  SplitMix64 rng(1);
  for (uint64_t v = 0; v < (1u << 20); ++v) {
    const uint64_t r = fx::isqrt_u64(v);
    ASSERT_LE(r * r, v);
    ASSERT_GT((r + 1) * (r + 1), v);
  }
  for (int i = 0; i < 1000000; ++i) {
    const uint64_t v = rng.next() >> (rng.next() % 64);
    const uint64_t r = fx::isqrt_u64(v);
    ASSERT_LE(r * r, v);
    // (r+1)^2 may exceed 2^64 only when r = 2^32 - 1.
    if (r < 0xFFFFFFFFu) ASSERT_GT((r + 1) * (r + 1), v);
  }
  report("isqrt_u64", 0.0, "(exact floor, 2^20 exhaustive + 10^6 random)");
}

TEST(FixedAccuracy, RsqrtWithinThreeLsb) {
  SplitMix64 rng(2);
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) {
    const uint64_t x = (uint64_t{1} << 58) + rng.next() % ((uint64_t{1} << 63) - (uint64_t{1} << 58));
    const double exact = kUnit / std::sqrt(static_cast<double>(x) / 1152921504606846976.0);
    worst = std::max(worst, std::fabs(fx::rsqrt_q60(x) - exact));
  }
  report("rsqrt_q60", worst, "LSB of Q2.30");
  EXPECT_LE(worst, 3.0);
}

TEST(FixedAccuracy, SinCosWithinOneLsb) {
  double worst = 0;
  auto check = [&](fx::Angle a) {
    const fx::SinCos sc = fx::sin_cos(a);
    const double t = angle_rad(a);
    worst = std::max(worst, std::fabs(sc.sin - std::sin(t) * kUnit));
    worst = std::max(worst, std::fabs(sc.cos - std::cos(t) * kUnit));
  };
  for (uint64_t a = 0; a < (uint64_t{1} << 32); a += 4093) check(static_cast<fx::Angle>(a));
  SplitMix64 rng(3);
  for (int i = 0; i < 200000; ++i) check(rng.next_u32());
  report("sin_cos", worst, "LSB of Q2.30");
  EXPECT_LE(worst, 1.0);  // target 4 LSB
}

TEST(FixedAccuracy, Atan2WithinTwoAngleLsb) {
  SplitMix64 rng(4);
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) {
    int32_t y = rng.next_i32() >> (rng.next() % 31);
    int32_t x = rng.next_i32() >> (rng.next() % 31);
    if (x == 0 && y == 0) continue;
    const double exact = std::atan2(static_cast<double>(y), static_cast<double>(x)) / kTwoPi * 4294967296.0;
    const double got = fx::angle_signed(fx::atan2_angle(y, x));
    double err = std::fabs(got - exact);
    if (err > 2147483648.0) err = 4294967296.0 - err;  // wrap at half turn
    worst = std::max(worst, err);
  }
  report("atan2_angle", worst, "LSB of the binary angle (2^-32 turn)");
  EXPECT_LE(worst, 2.0);
}

namespace {
fx::Quat random_unit_quat(SplitMix64& rng) {
  fx::Vec3 axis{rng.next_i32() >> 2, rng.next_i32() >> 2, rng.next_i32() >> 2};
  fx::Vec3 unit;
  if (!fx::normalize_to_unit(axis, &unit)) unit = {fx::kUnitOne, 0, 0};
  return fx::quat_from_axis_angle(unit, rng.next_u32());
}
}  // namespace

TEST(FixedAccuracy, QuatProductIsExactlyRounded) {
  SplitMix64 rng(5);
  double worst = 0;
  for (int i = 0; i < 200000; ++i) {
    const fx::Quat a = random_unit_quat(rng), b = random_unit_quat(rng);
    const fx::Quat p = fx::mul(a, b);
    const long double aw = a.w, ax = a.x, ay = a.y, az = a.z, bw = b.w, bx = b.x, by = b.y, bz = b.z;
    const long double s = 1073741824.0L;
    const long double ref[4] = {
        (aw * bw - ax * bx - ay * by - az * bz) / s, (aw * bx + ax * bw + ay * bz - az * by) / s,
        (aw * by - ax * bz + ay * bw + az * bx) / s, (aw * bz + ax * by - ay * bx + az * bw) / s};
    const int32_t got[4] = {p.w, p.x, p.y, p.z};
    for (int k = 0; k < 4; ++k) worst = std::max(worst, static_cast<double>(std::fabs(got[k] - ref[k])));
  }
  report("quat mul", worst, "LSB of Q2.30 (vs exact product)");
  EXPECT_LE(worst, 2.0);  // target: 2 LSB of the exact rounded result
}

TEST(FixedAccuracy, MatrixProductWithinTwoLsb) {
  SplitMix64 rng(6);
  double worst_lin = 0, worst_t = 0;
  for (int i = 0; i < 100000; ++i) {
    const fx::Mat34 a = fx::mat34_from_quat(random_unit_quat(rng), {rng.range(-fx::kLenOne * 4, fx::kLenOne * 4),
                                                                    rng.next_i32() >> 9, rng.next_i32() >> 9});
    const fx::Mat34 b = fx::mat34_from_trs(
        {rng.next_i32() >> 9, rng.next_i32() >> 9, rng.next_i32() >> 9}, random_unit_quat(rng),
        {rng.range(fx::kLinOne / 4, fx::kLinOne * 4), rng.range(fx::kLinOne / 4, fx::kLinOne * 4), fx::kLinOne});
    const fx::Mat34 c = fx::mul(a, b);
    for (int r = 0; r < 3; ++r) {
      long double t = static_cast<long double>(a.t[r]) * 16777216.0L;
      for (int k = 0; k < 3; ++k) {
        long double m = 0;
        for (int j = 0; j < 3; ++j) m += static_cast<long double>(a.m[r][j]) * b.m[j][k];
        worst_lin = std::max(worst_lin, static_cast<double>(std::fabs(c.m[r][k] - m / 16777216.0L)));
        t += static_cast<long double>(a.m[r][k]) * b.t[k];
      }
      worst_t = std::max(worst_t, static_cast<double>(std::fabs(c.t[r] - t / 16777216.0L)));
    }
  }
  report("mat34 mul (linear)", worst_lin, "LSB of Q8.24 (vs exact product)");
  report("mat34 mul (transl.)", worst_t, "LSB of Q12.20 (vs exact product)");
  EXPECT_LE(worst_lin, 2.0);
  EXPECT_LE(worst_t, 2.0);
}

TEST(FixedAccuracy, RotationFromQuatWithinOneLsb) {
  SplitMix64 rng(7);
  double worst = 0;
  for (int i = 0; i < 200000; ++i) {
    const fx::Quat q = random_unit_quat(rng);
    const fx::Rot3 r = fx::rot3_from_quat(q);
    const long double w = q.w / 1073741824.0L, x = q.x / 1073741824.0L, y = q.y / 1073741824.0L,
                      z = q.z / 1073741824.0L;
    const long double ref[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                                   {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                                   {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        worst = std::max(worst, static_cast<double>(std::fabs(r.m[a][b] - ref[a][b] * 1073741824.0L)));
  }
  report("rot3_from_quat", worst, "LSB of Q2.30 (vs exact formula)");
  EXPECT_LE(worst, 1.0);
}

TEST(FixedAccuracy, NormalizationWithinBounds) {
  SplitMix64 rng(8);
  double worst_q = 0, worst_v = 0;
  for (int i = 0; i < 200000; ++i) {
    fx::Quat q{rng.next_i32() >> 2, rng.next_i32() >> 2, rng.next_i32() >> 2, rng.next_i32() >> 2};
    const long double n = std::sqrt(static_cast<long double>(q.w) * q.w + static_cast<long double>(q.x) * q.x +
                                    static_cast<long double>(q.y) * q.y + static_cast<long double>(q.z) * q.z);
    const fx::Quat in = q;
    if (!fx::normalize(&q)) continue;
    worst_q = std::max(worst_q, static_cast<double>(std::fabs(q.x - in.x / n * 1073741824.0L)));
    worst_q = std::max(worst_q, static_cast<double>(std::fabs(q.w - in.w / n * 1073741824.0L)));
    const fx::Vec3 v{rng.next_i32() >> (rng.next() % 31), rng.next_i32() >> (rng.next() % 31), rng.next_i32()};
    fx::Vec3 u;
    if (!fx::normalize_to_unit(v, &u)) continue;
    const long double vn = std::sqrt(static_cast<long double>(v.x) * v.x + static_cast<long double>(v.y) * v.y +
                                     static_cast<long double>(v.z) * v.z);
    worst_v = std::max(worst_v, static_cast<double>(std::fabs(u.x - v.x / vn * 1073741824.0L)));
    worst_v = std::max(worst_v, static_cast<double>(std::fabs(u.z - v.z / vn * 1073741824.0L)));
  }
  report("quat normalize", worst_q, "LSB of Q2.30");
  report("vec3 normalize_to_unit", worst_v, "LSB of Q2.30");
  EXPECT_LE(worst_q, 1.5);
  EXPECT_LE(worst_v, 2.5);  // inputs >= 2^30 lose up to two bits in the pre-scale
}

#include "sim_core/fixed/rsqrt_fast.hpp"

TEST(FixedAccuracy, DivisionFreeNormalizationWithinFourLsb) {
  SplitMix64 rng(9);
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) {
    const fx::Vec3 v{rng.next_i32() >> (rng.next() % 31), rng.next_i32() >> (rng.next() % 31),
                     rng.next_i32() >> (rng.next() % 31)};
    fx::Vec3 u;
    if (!fx::normalize_fast(v, &u)) continue;
    const long double n = std::sqrt(static_cast<long double>(v.x) * v.x + static_cast<long double>(v.y) * v.y +
                                    static_cast<long double>(v.z) * v.z);
    const int32_t got[3] = {u.x, u.y, u.z};
    const int32_t in[3] = {v.x, v.y, v.z};
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, static_cast<double>(std::fabs(got[c] - in[c] / n * 1073741824.0L)));
  }
  report("normalize_fast (vec3)", worst, "LSB of Q2.30");
  EXPECT_LE(worst, 4.0);
}
