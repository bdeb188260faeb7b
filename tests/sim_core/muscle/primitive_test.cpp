// Implicit muscle primitives: inside tests, gradients against finite
// differences of a double oracle, push-out lands on the surface.
#include "sim_core/muscle/primitive.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace muscle = sinew::muscle;
namespace fx = sinew::fx;

namespace {

constexpr double kLsb = 1.0 / (1 << 20);  // Len LSB in rig units

muscle::PrimitiveFrame frame(muscle::PrimitiveKind kind, int exponent, double a, double b, double c) {
  muscle::PrimitiveFrame f;
  f.kind = static_cast<uint8_t>(kind);
  f.exponent = static_cast<uint8_t>(exponent);
  f.active = 1;
  f.centre = {1 << 20, -(2 << 20), 3 << 19};
  // Axes: a rotation of 90 degrees about z (x -> y, y -> -x).
  f.axis[0] = {0, fx::kUnitOne, 0};
  f.axis[1] = {-fx::kUnitOne, 0, 0};
  f.axis[2] = {0, 0, fx::kUnitOne};
  f.extent[0] = static_cast<fx::Len>(a / kLsb);
  f.extent[1] = static_cast<fx::Len>(b / kLsb);
  f.extent[2] = static_cast<fx::Len>(c / kLsb);
  return f;
}

// Double oracle of F in the frame above.
double oracle(const muscle::PrimitiveFrame& f, const double p[3]) {
  const double d[3] = {p[0] - f.centre.x * kLsb, p[1] - f.centre.y * kLsb, p[2] - f.centre.z * kLsb};
  const double local[3] = {d[1], -d[0], d[2]};
  const bool cyl = f.kind == static_cast<uint8_t>(muscle::PrimitiveKind::kCylinder);
  const int e = f.kind == static_cast<uint8_t>(muscle::PrimitiveKind::kSuperellipsoid) ? f.exponent : 2;
  double sum = 0;
  for (int i = 0; i < (cyl ? 2 : 3); ++i) sum += std::pow(std::fabs(local[i] / (f.extent[i] * kLsb)), e);
  return sum;
}

// Its gradient dF/dx_i = p sign(q_i) |q_i|^(p-1) / a_i, turned back to world
// axes (local x = world y, local y = -world x).
void oracle_gradient(const muscle::PrimitiveFrame& f, const double p[3], double g[3]) {
  const double d[3] = {p[0] - f.centre.x * kLsb, p[1] - f.centre.y * kLsb, p[2] - f.centre.z * kLsb};
  const double local[3] = {d[1], -d[0], d[2]};
  const bool cyl = f.kind == static_cast<uint8_t>(muscle::PrimitiveKind::kCylinder);
  const int e = f.kind == static_cast<uint8_t>(muscle::PrimitiveKind::kSuperellipsoid) ? f.exponent : 2;
  double gl[3] = {0, 0, 0};
  for (int i = 0; i < (cyl ? 2 : 3); ++i) {
    const double a = f.extent[i] * kLsb, q = local[i] / a;
    gl[i] = e * std::copysign(std::pow(std::fabs(q), e - 1), q) / a;
  }
  g[0] = -gl[1], g[1] = gl[0], g[2] = gl[2];
}

fx::Vec3 to_len(const double p[3]) {
  return {static_cast<int32_t>(std::llround(p[0] / kLsb)), static_cast<int32_t>(std::llround(p[1] / kLsb)),
          static_cast<int32_t>(std::llround(p[2] / kLsb))};
}

}  // namespace

TEST(Primitive, InsideValueAndGradientMatchADoubleOracle) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  const muscle::PrimitiveFrame shapes[] = {frame(muscle::PrimitiveKind::kSphere, 2, 0.5, 0.5, 0.5),
                                           frame(muscle::PrimitiveKind::kCylinder, 2, 0.4, 0.3, 1.0),
                                           frame(muscle::PrimitiveKind::kSuperellipsoid, 4, 0.6, 0.3, 0.9),
                                           frame(muscle::PrimitiveKind::kSuperellipsoid, 8, 0.2, 0.5, 0.4)};
  for (const auto& f : shapes) {
    const bool cyl = f.kind == static_cast<uint8_t>(muscle::PrimitiveKind::kCylinder);
    const int e = f.kind == static_cast<uint8_t>(muscle::PrimitiveKind::kSuperellipsoid) ? f.exponent : 2;
    const int terms = cyl ? 2 : 3;
    // F: q = local / a rounds to Q2.30 (2^-31; local is exact on these
    // axis-aligned frames); each squaring doubles the error and rounds once
    // more (q^2: 3, q^4: 7, q^8: 15 x 2^-31, i.e. (2p - 1) 2^-31), per term.
    const double value_bound = terms * (2 * e - 1) * 0x1p-31;
    // Gradient direction: q^(p-1) is off by (2p - 3) 2^-31 (q, then one
    // rounding per product), the factor emax / a_i by half a Q16 unit of a
    // value >= 2^16 (2^-17 relative); the 30-bit narrowing and the Q2.30
    // normalisation add a few 2^-30. So the angle is below
    // p (2p - 3) 2^-31 |1/a| / |grad F| + 2^-17 + 2^-28 (|1/a|: the
    // reciprocal extents' norm), per point.
    double inv_a = 0;
    for (int i = 0; i < terms; ++i) inv_a += 1 / std::pow(f.extent[i] * kLsb, 2);
    inv_a = std::sqrt(inv_a);
    double worst_value = 0, worst_angle = 0, worst_angle_ratio = 0, worst_length = 0;
    int inside = 0, mismatched = 0;
    for (int i = 0; i < 20000; ++i) {
      const double p[3] = {f.centre.x * kLsb + u(rng) * f.extent[1] * kLsb,
                           f.centre.y * kLsb + u(rng) * f.extent[0] * kLsb,
                           f.centre.z * kLsb + u(rng) * f.extent[2] * kLsb};
      // The oracle sees the quantised point the kernel sees.
      const fx::Vec3 pq = to_len(p);
      const double p_q[3] = {pq.x * kLsb, pq.y * kLsb, pq.z * kLsb};
      const muscle::PrimitiveSample s = muscle::primitive_sample(f, pq);
      const double want = oracle(f, p_q);
      if (s.value >= (int64_t{4} << 30)) continue;  // outside the box
      worst_value = std::max(worst_value, std::fabs(std::ldexp(static_cast<double>(s.value), -30) - want));
      // Within the value bound of 1 the rounded F may fall either side.
      mismatched += (s.inside != (want < 1)) && std::fabs(want - 1) > value_bound;
      inside += s.inside;
      double g[3];
      oracle_gradient(f, p_q, g);
      const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
      if (gn == 0) continue;
      const double n[3] = {std::ldexp(s.normal.x, -30), std::ldexp(s.normal.y, -30), std::ldexp(s.normal.z, -30)};
      // Angle from the cross and dot products: independent of |n|, whose
      // own rounding is checked apart (norm rounded to 2^-31 relative, each
      // component to 2^-31).
      const double cr[3] = {g[1] * n[2] - g[2] * n[1], g[2] * n[0] - g[0] * n[2], g[0] * n[1] - g[1] * n[0]};
      const double angle =
          std::atan2(std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]), g[0] * n[0] + g[1] * n[1] + g[2] * n[2]);
      const double angle_bound = e * (2 * e - 3) * 0x1p-31 * inv_a / gn + 0x1p-17 + 0x1p-28;
      worst_angle = std::max(worst_angle, angle);
      worst_angle_ratio = std::max(worst_angle_ratio, angle / angle_bound);
      worst_length = std::max(worst_length, std::fabs(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1));
    }
    std::printf(
        "primitive kind %d p=%d: %d inside of 20000, worst |F - oracle| %.3g (bound %.3g), worst gradient angle %.3g "
        "rad (%.3f of its bound), worst ||n| - 1| %.3g\n",
        f.kind, f.exponent, inside, worst_value, value_bound, worst_angle, worst_angle_ratio, worst_length);
    EXPECT_EQ(mismatched, 0);
    EXPECT_LE(worst_value, value_bound);
    EXPECT_LE(worst_angle_ratio, 1.0);
    EXPECT_LE(worst_length, (1 + std::sqrt(3.0)) * 0x1p-31);
    EXPECT_GT(inside, 1000);
  }
}

TEST(Primitive, PushOutLandsJustOutsideAlongTheGradient) {
  const muscle::PrimitiveFrame f = frame(muscle::PrimitiveKind::kSuperellipsoid, 4, 0.6, 0.3, 0.9);
  const double a_min = 0.3;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  double worst_shallow = 0, worst_deep = 0, worst_ratio = 0;
  int still_inside = 0, tried = 0, shallow = 0;
  for (int i = 0; i < 5000; ++i) {
    const double p[3] = {f.centre.x * kLsb + u(rng) * 0.3, f.centre.y * kLsb + u(rng) * 0.6,
                         f.centre.z * kLsb + u(rng) * 0.9};
    const double before = oracle(f, p);
    if (before >= 1) continue;
    ++tried;
    const fx::Vec3 start = to_len(p);
    const fx::Vec3 out = muscle::primitive_push_out(f, start, {0, 0, fx::kUnitOne}, 3);
    const double q[3] = {out.x * kLsb, out.y * kLsb, out.z * kLsb};
    const double value = oracle(f, q);
    still_inside += value < 1 - 1.0 / 1024;
    // Skin points reach a primitive from outside: shallow penetrations
    // (F >= 0.5) are the regime that matters; deep ones only must get out.
    if (before < 0.5) {
      worst_deep = std::max(worst_deep, value - 1);
      continue;
    }
    ++shallow;
    worst_shallow = std::max(worst_shallow, value - 1);
    // G = F^(1/4) is a norm (convex, degree 1), so Newton's step
    // delta = (1 - G) / |grad G| along the unit gradient n lands outside,
    // and by the triangle inequality at G + delta G(n) at most: the
    // overshoot is bounded by the penetration 1 - G times G(n) / |grad G|,
    // and one step suffices. Rounding: the kernel's step adds 1 LSB, its
    // direction and length carry a few 2^-17 (4 allowed; the gradient's factor
    // emax / a_i in Q16), the landing point rounds (0.5 LSB per axis); G
    // moves by at most |dx| / a_min.
    const double p_q[3] = {start.x * kLsb, start.y * kLsb, start.z * kLsb};
    const double g0 = std::pow(oracle(f, p_q), 0.25);
    double gf[3];
    oracle_gradient(f, p_q, gf);
    const double gf_len = std::sqrt(gf[0] * gf[0] + gf[1] * gf[1] + gf[2] * gf[2]);
    const double n[3] = {gf[0] / gf_len, gf[1] / gf_len, gf[2] / gf_len};
    const double grad_g = gf_len / (4 * std::pow(g0, 3));  // |grad G| = |grad F| / (4 G^3)
    const double delta = (1 - g0) / grad_g;
    const double p_n[3] = {f.centre.x * kLsb + n[0], f.centre.y * kLsb + n[1], f.centre.z * kLsb + n[2]};
    const double g_of_n = std::pow(oracle(f, p_n), 0.25);
    const double bound = g0 + delta * g_of_n + (delta * 0x1p-15 + 3 * kLsb) / a_min;
    worst_ratio = std::max(worst_ratio, (std::pow(value, 0.25) - 1) / (bound - 1));
  }
  std::printf(
      "push-out (3 Newton steps): %d points inside, %d still inside beyond 2^-10; overshoot F-1: shallow "
      "(F >= 0.5, %d points) %.3g, at most %.3f of its convexity bound; deep %.3g\n",
      tried, still_inside, shallow, worst_shallow, worst_ratio, worst_deep);
  EXPECT_GT(tried, 500);
  EXPECT_EQ(still_inside, 0);
  EXPECT_LE(worst_ratio, 1.0) << "shallow points land no farther out than one Newton step on G can carry them";
}
