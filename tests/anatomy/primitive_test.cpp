// Implicit muscle primitives: inside tests, gradients against finite
// differences of a double oracle, push-out lands on the surface.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "sim_core/muscle/primitive.hpp"

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
    double worst_value = 0, worst_angle = 0;
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
      mismatched += (s.inside != (want < 1)) && std::fabs(want - 1) > 1e-6;
      inside += s.inside;
      // Gradient direction vs central differences of the oracle.
      const double h = 1e-6;
      double g[3];
      for (int c = 0; c < 3; ++c) {
        double a[3] = {p_q[0], p_q[1], p_q[2]}, b[3] = {p_q[0], p_q[1], p_q[2]};
        a[c] += h, b[c] -= h;
        g[c] = (oracle(f, a) - oracle(f, b)) / (2 * h);
      }
      const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
      if (gn < 1e-3) continue;
      const double n[3] = {std::ldexp(s.normal.x, -30), std::ldexp(s.normal.y, -30), std::ldexp(s.normal.z, -30)};
      const double cosang = (g[0] * n[0] + g[1] * n[1] + g[2] * n[2]) / gn;
      worst_angle = std::max(worst_angle, std::acos(std::min(1.0, cosang)));
    }
    std::printf("primitive kind %d p=%d: %d inside of 20000, worst |F - oracle| %.3g, worst gradient angle %.3g rad\n",
                f.kind, f.exponent, inside, worst_value, worst_angle);
    EXPECT_EQ(mismatched, 0);
    EXPECT_LT(worst_value, 1e-6);
    EXPECT_LT(worst_angle, 1e-4);
    EXPECT_GT(inside, 1000);
  }
}

TEST(Primitive, PushOutLandsJustOutsideAlongTheGradient) {
  const muscle::PrimitiveFrame f = frame(muscle::PrimitiveKind::kSuperellipsoid, 4, 0.6, 0.3, 0.9);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  double worst_shallow = 0, worst_deep = 0;
  int still_inside = 0, tried = 0, shallow = 0;
  for (int i = 0; i < 5000; ++i) {
    const double p[3] = {f.centre.x * kLsb + u(rng) * 0.3, f.centre.y * kLsb + u(rng) * 0.6,
                         f.centre.z * kLsb + u(rng) * 0.9};
    const double before = oracle(f, p);
    if (before >= 1) continue;
    ++tried;
    const fx::Vec3 out = muscle::primitive_push_out(f, to_len(p), {0, 0, fx::kUnitOne}, 3);
    const double q[3] = {out.x * kLsb, out.y * kLsb, out.z * kLsb};
    const double value = oracle(f, q);
    still_inside += value < 1 - 1.0 / 1024;
    // Skin points reach a primitive from outside: shallow penetrations
    // (F >= 0.5) are the regime that matters; deep ones only must get out.
    if (before >= 0.5) {
      ++shallow;
      worst_shallow = std::max(worst_shallow, value - 1);
    } else {
      worst_deep = std::max(worst_deep, value - 1);
    }
  }
  std::printf(
      "push-out (3 Newton steps): %d points inside, %d still inside beyond 2^-10; overshoot F-1: shallow "
      "(F >= 0.5, %d points) %.3g, deep %.3g\n",
      tried, still_inside, shallow, worst_shallow, worst_deep);
  EXPECT_GT(tried, 500);
  EXPECT_EQ(still_inside, 0);
  EXPECT_LT(worst_shallow, 0.2) << "shallow points land near the surface (F^(1/4) within 5 %)";
}
