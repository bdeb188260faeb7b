// General superquadric primitives (sim_core/muscle/superquadric.hpp) against
// a double oracle written from Barr's formula (LEMAN §5.2, [Barr 81]):
//   F = (|x/a|^pxy + |y/b|^pxy)^(pz/pxy) + |z/c|^pz,
//   dF/dx = pz S^(pz/pxy - 1) |x/a|^(pxy-1) sign(x) / a, ...
// Every bound is the header's derivation from the Q formats (u = 2^-30):
//   |F - F_oracle| <= [ln 2 (pz + e + 1/2) F + 1.01] u, e = pz / pxy;
//   gradient angle <= (2 ln 2 dL + 6) u, dL = max(|e - 1| (pxy + 1) + pxy + 1,
//   pz + 0.5) the worst error of a component's log2 (in u), 6 u the direction's
//   rounding to Q2.30 and its normalisation.
#include "sim_core/muscle/superquadric.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "sim_core/muscle/primitive.hpp"

namespace muscle = sinew::muscle;
namespace fx = sinew::fx;

namespace {

constexpr double kSqLsb = 1.0 / (1 << 20);  // Len LSB in rig units
constexpr double kU = 1.0 / 1073741824.0;   // 2^-30
constexpr double kLn2 = 0.69314718055994530942;

struct SqShape {
  double pxy, pz;  // exponents (rounded to Q16.16 by sq_frame; the oracle reads them back)
  double a, b, c;  // half-extents, rig units
};

// A superellipsoid turned 90 degrees about z (local x = world y, local y =
// -world x: exact in fixed point), general kernel unless `exact`.
muscle::PrimitiveFrame sq_frame(const SqShape& s, bool exact = false) {
  muscle::PrimitiveFrame f;
  f.kind = static_cast<uint8_t>(muscle::PrimitiveKind::kSuperellipsoid);
  f.active = 1;
  f.centre = {1 << 20, -(2 << 20), 3 << 19};
  f.axis[0] = {0, fx::kUnitOne, 0};
  f.axis[1] = {-fx::kUnitOne, 0, 0};
  f.axis[2] = {0, 0, fx::kUnitOne};
  f.extent[0] = static_cast<fx::Len>(std::llround(s.a / kSqLsb));
  f.extent[1] = static_cast<fx::Len>(std::llround(s.b / kSqLsb));
  f.extent[2] = static_cast<fx::Len>(std::llround(s.c / kSqLsb));
  f.superquadric.power_xy = static_cast<int32_t>(std::llround(s.pxy * 65536));
  f.superquadric.power_z = static_cast<int32_t>(std::llround(s.pz * 65536));
  f.exponent = exact ? static_cast<uint8_t>(s.pxy) : 0;
  muscle::superquadric_prepare(&f);
  return f;
}

double sq_pxy(const muscle::PrimitiveFrame& f) { return f.superquadric.power_xy / 65536.0; }
double sq_pz(const muscle::PrimitiveFrame& f) { return f.superquadric.power_z / 65536.0; }

struct SqOracle {
  double f = 0;
  double grad[3] = {0, 0, 0};  // world dF/dx, per rig unit
};

// Barr's F and gradient at a world point (Len), in double.
SqOracle sq_oracle(const muscle::PrimitiveFrame& f, fx::Vec3 p) {
  const double pxy = sq_pxy(f), pz = sq_pz(f), e = pz / pxy;
  const double d[3] = {static_cast<double>(p.x) - f.centre.x, static_cast<double>(p.y) - f.centre.y,
                       static_cast<double>(p.z) - f.centre.z};
  const double local[3] = {d[1], -d[0], d[2]};
  double q[3], sign[3];
  for (int i = 0; i < 3; ++i) {
    q[i] = std::fabs(local[i]) / f.extent[i];
    sign[i] = (local[i] > 0) - (local[i] < 0);
  }
  const double s = std::pow(q[0], pxy) + std::pow(q[1], pxy);
  SqOracle o;
  o.f = (s > 0 ? std::pow(s, e) : 0) + std::pow(q[2], pz);
  double g[3] = {0, 0, 0};  // local, per rig unit
  for (int i = 0; i < 2; ++i)
    if (q[i] > 0) g[i] = pz * std::pow(s, e - 1) * std::pow(q[i], pxy - 1) * sign[i] / (f.extent[i] * kSqLsb);
  if (q[2] > 0) g[2] = pz * std::pow(q[2], pz - 1) * sign[2] / (f.extent[2] * kSqLsb);
  o.grad[0] = -g[1];
  o.grad[1] = g[0];
  o.grad[2] = g[2];
  return o;
}

double sq_value_bound(const muscle::PrimitiveFrame& f, double value) {
  const double pxy = sq_pxy(f), pz = sq_pz(f), e = pz / pxy;
  return (kLn2 * (pz + e + 0.5) * value + 1.01) * kU + 1e-15;
}

double sq_log_error(const muscle::PrimitiveFrame& f) {  // dL, in u
  const double pxy = sq_pxy(f), pz = sq_pz(f), e = pz / pxy;
  return std::max(std::fabs(e - 1) * (pxy + 1) + pxy + 1, pz + 0.5);
}

double sq_angle_bound(const muscle::PrimitiveFrame& f) { return (2 * kLn2 * sq_log_error(f) + 6) * kU; }

double sq_angle(const double g[3], fx::Vec3 n) {
  const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  const double nn[3] = {n.x * kU, n.y * kU, n.z * kU};
  const double c = (g[0] * nn[0] + g[1] * nn[1] + g[2] * nn[2]) / gn;
  const double cross[3] = {g[1] * nn[2] - g[2] * nn[1], g[2] * nn[0] - g[0] * nn[2], g[0] * nn[1] - g[1] * nn[0]};
  return std::atan2(std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]) / gn, c);
}

fx::Vec3 sq_point(const muscle::PrimitiveFrame& f, std::mt19937& rng, double reach) {
  std::uniform_real_distribution<double> u(-reach, reach);
  // World x spans local y (extent 1), world y local x (extent 0).
  return {f.centre.x + static_cast<int32_t>(std::llround(u(rng) * f.extent[1])),
          f.centre.y + static_cast<int32_t>(std::llround(u(rng) * f.extent[0])),
          f.centre.z + static_cast<int32_t>(std::llround(u(rng) * f.extent[2]))};
}

const SqShape kSqShapes[] = {
    {1, 1, 0.6, 0.3, 0.9},     {1.5, 1.5, 0.5, 0.4, 0.3}, {2.5, 2.5, 0.6, 0.3, 0.9},  {3, 3, 0.2, 0.5, 0.4},
    {6.5, 6.5, 0.4, 0.4, 0.8}, {16, 16, 0.6, 0.3, 0.9},   {3, 2.5, 0.4, 0.25, 0.6},   {1, 16, 0.5, 0.3, 0.7},
    {16, 1, 0.3, 0.6, 0.5},    {6.5, 1.5, 0.5, 0.2, 0.9}, {1.5, 6.5, 0.25, 0.5, 0.4},
};

}  // namespace

TEST(Superquadric, ValueAndGradientMatchBarrsFormula) {
  std::mt19937 rng(17);
  for (const SqShape& shape : kSqShapes) {
    const muscle::PrimitiveFrame f = sq_frame(shape);
    ASSERT_TRUE(muscle::is_general_superquadric(f));
    double worst_value = 0, worst_value_ratio = 0, worst_angle = 0;
    int inside = 0, tested = 0;
    for (int i = 0; i < 20000; ++i) {
      const fx::Vec3 p = sq_point(f, rng, 1.2);
      const muscle::PrimitiveSample s = muscle::primitive_sample(f, p);
      if (s.value >= (int64_t{4} << 30)) continue;  // outside the box (or capped)
      ++tested;
      const SqOracle o = sq_oracle(f, p);
      const double err = std::fabs(std::ldexp(static_cast<double>(s.value), -30) - o.f);
      const double bound = sq_value_bound(f, o.f);
      worst_value = std::max(worst_value, err);
      worst_value_ratio = std::max(worst_value_ratio, err / bound);
      ASSERT_LE(err, bound) << "p " << shape.pxy << "/" << shape.pz << " F " << o.f;
      if (std::fabs(o.f - 1) > bound) ASSERT_EQ(s.inside, o.f < 1) << "F " << o.f;
      inside += s.inside;
      if (o.grad[0] == 0 && o.grad[1] == 0 && o.grad[2] == 0) continue;
      const double angle = sq_angle(o.grad, s.normal);
      worst_angle = std::max(worst_angle, angle);
      ASSERT_LE(angle, sq_angle_bound(f)) << "p " << shape.pxy << "/" << shape.pz;
    }
    std::printf(
        "superquadric p_xy %.1f p_z %.1f: %d in the box, %d inside; worst |F - oracle| %.3g (%.2f of the bound), "
        "worst gradient angle %.3g rad (bound %.3g)\n",
        shape.pxy, shape.pz, tested, inside, worst_value, worst_value_ratio, worst_angle, sq_angle_bound(f));
    EXPECT_GT(inside, 1000);
  }
}

// p = 2, 4, 8 through the general kernel against the exact integer kernel.
// The exact kernel's own error (u = 2^-30): each q rounded by u/2, each
// power chain q^p off by (p - 1/2) u and q^(p-1) by (p - 1) u; its axis
// ratios emax / a_i are Q16 (2^-17 relative).
TEST(Superquadric, GeneralKernelAgreesWithTheExactOneAtTwoFourEight) {
  std::mt19937 rng(23);
  for (const double p : {2.0, 4.0, 8.0}) {
    const SqShape shape{p, p, 0.6, 0.3, 0.9};
    const muscle::PrimitiveFrame general = sq_frame(shape), exact = sq_frame(shape, true);
    ASSERT_TRUE(muscle::is_general_superquadric(general));
    ASSERT_FALSE(muscle::is_general_superquadric(exact));
    double worst_value = 0, worst_angle = 0, worst_shallow = 0;
    for (int i = 0; i < 20000; ++i) {
      const fx::Vec3 pt = sq_point(general, rng, 1.1);
      const muscle::PrimitiveSample g = muscle::primitive_sample(general, pt);
      const muscle::PrimitiveSample x = muscle::primitive_sample(exact, pt);
      if (x.value >= (int64_t{4} << 30)) {  // outside the box: both say so
        ASSERT_EQ(g.value, x.value);
        continue;
      }
      const SqOracle o = sq_oracle(general, pt);
      const double value_bound = sq_value_bound(general, o.f) + 3 * (p - 0.5) * kU;
      const double err = std::fabs(static_cast<double>(g.value - x.value)) * kU;
      worst_value = std::max(worst_value, err);
      ASSERT_LE(err, value_bound) << "p " << p << " F " << o.f;
      const double gn = std::sqrt(o.grad[0] * o.grad[0] + o.grad[1] * o.grad[1] + o.grad[2] * o.grad[2]);
      // Deep inside, the exact kernel's q^(p-1) underflow Q2.30 and leave no
      // direction (the general kernel keeps one): nothing to compare.
      if (gn == 0 || x.normal == fx::Vec3{0, 0, 0}) continue;
      // The exact kernel's direction: its components p q^(p-1) emax / a_i are
      // off by p (p - 1) u emax / a_i each plus 2^-17 relative.
      double inv_extent2 = 0;
      for (int c = 0; c < 3; ++c) inv_extent2 += 1 / (exact.extent[c] * kSqLsb * exact.extent[c] * kSqLsb);
      const double exact_angle = 0x1p-17 + p * (p - 1) * kU * std::sqrt(inv_extent2) / gn + 6 * kU;
      double gx[3] = {std::ldexp(static_cast<double>(x.normal.x), -30),
                      std::ldexp(static_cast<double>(x.normal.y), -30),
                      std::ldexp(static_cast<double>(x.normal.z), -30)};
      const double angle = sq_angle(gx, g.normal);
      worst_angle = std::max(worst_angle, angle);
      if (o.f >= 0.5) worst_shallow = std::max(worst_shallow, angle);
      ASSERT_LE(angle, exact_angle + sq_angle_bound(general)) << "p " << p;
    }
    std::printf(
        "superquadric general vs exact kernel, p = %.0f: worst |F difference| %.3g, worst angle %.3g rad (%.3g where F "
        ">= 0.5)\n",
        p, worst_value, worst_angle, worst_shallow);
  }
}

// The push-out's Newton step on G = F^(1/p_z) (convex and homogeneous of
// degree 1): from inside it lands on or outside the surface, so no point is
// left inside: the kernel's own F says outside after the push, and Barr's F
// there is at least 1 minus the kernel's F bound at 1. Shallow points (G >=
// 0.9) land where the oracle's own Newton step lands, within the step's
// rounding: the step length (1 - G) / |grad G| is formed from about eight
// logarithms in the log domain, each off by at most the F and gradient
// bounds above, 1 - G by u / (1 - G) relative; then 1 LSB of nudge and the
// Len rounding of the move; G is sqrt(3) / min extent Lipschitz.
TEST(Superquadric, PushOutLandsOnTheSurfaceAndNeverLeavesAPointInside) {
  std::mt19937 rng(29);
  for (const SqShape& shape : kSqShapes) {
    const muscle::PrimitiveFrame f = sq_frame(shape);
    const double pz = sq_pz(f), e = pz / sq_pxy(f);
    const double a_min = std::min({f.extent[0], f.extent[1], f.extent[2]}) * kSqLsb;
    int tried = 0, shallow = 0, left_inside = 0;
    double lowest = 2, worst_landing = 0, worst_overshoot = 0;
    for (int i = 0; i < 4000; ++i) {
      const fx::Vec3 p = sq_point(f, rng, 0.95);
      const SqOracle before = sq_oracle(f, p);
      if (before.f >= 1) continue;
      ++tried;
      const fx::Vec3 out = muscle::primitive_push_out(f, p, {0, 0, fx::kUnitOne}, 3);
      left_inside += muscle::primitive_sample(f, out).inside;
      const double after = sq_oracle(f, out).f;
      lowest = std::min(lowest, after);
      ASSERT_GE(after, 1 - sq_value_bound(f, 1)) << "p " << shape.pxy << "/" << shape.pz;
      const double g0 = std::pow(before.f, 1 / pz);
      if (g0 < 0.9) continue;
      ++shallow;
      // One kernel step against the oracle's exact Newton step.
      const fx::Vec3 one = muscle::primitive_push_out(f, p, {0, 0, fx::kUnitOne}, 1);
      const double gn = std::sqrt(before.grad[0] * before.grad[0] + before.grad[1] * before.grad[1] +
                                  before.grad[2] * before.grad[2]);
      const double grad_g = g0 / (pz * before.f) * gn;  // |grad G| per rig unit
      const double delta = (1 - g0) / grad_g;
      double target[3] = {p.x * kSqLsb, p.y * kSqLsb, p.z * kSqLsb};
      for (int c = 0; c < 3; ++c) target[c] += delta * before.grad[c] / gn;
      const fx::Vec3 target_len{static_cast<int32_t>(std::llround(target[0] / kSqLsb)),
                                static_cast<int32_t>(std::llround(target[1] / kSqLsb)),
                                static_cast<int32_t>(std::llround(target[2] / kSqLsb))};
      const double g_target = std::pow(sq_oracle(f, target_len).f, 1 / pz);
      const double g_one = std::pow(sq_oracle(f, one).f, 1 / pz);
      const double rho = kLn2 * (2 * (pz + e + 1) + 2 * sq_log_error(f) + 4) * kU + 2 * kU / (1 - g0);
      const double move_error = delta * (rho + sq_angle_bound(f)) + (2 + std::sqrt(3.0)) * kSqLsb;  // + target rounding
      const double tolerance = std::sqrt(3.0) / a_min * move_error;
      worst_landing = std::max(worst_landing, std::fabs(g_one - g_target) / tolerance);
      worst_overshoot = std::max(worst_overshoot, g_one - 1);
      ASSERT_NEAR(g_one, g_target, tolerance) << "p " << shape.pxy << "/" << shape.pz << " G0 " << g0;
      ASSERT_GE(g_target, 1 - tolerance) << "the oracle's Newton step lands outside (G convex)";
    }
    std::printf(
        "superquadric push-out p_xy %.1f p_z %.1f: %d inside points, %d left inside; lowest F after %.9f; shallow "
        "(G >= 0.9) %d: landing vs the oracle's Newton step %.2f of its tolerance, worst G - 1 %.3g\n",
        shape.pxy, shape.pz, tried, left_inside, lowest, shallow, worst_landing, worst_overshoot);
    EXPECT_GT(tried, 200);
    EXPECT_EQ(left_inside, 0);
    EXPECT_GT(shallow, 20);
  }
}

// The general kernel at the limits the runtime can produce (as
// PrimitiveExtremes for the exact one): a muscle-attached primitive's
// extents follow the muscle, so aspect ratios reach far beyond the
// validator's 64 and extents the whole Len range. Sampling and pushing out
// stay defined (the sanitizer builds abort on signed overflow), keep a unit
// normal, and a point pushed out is no longer inside.
TEST(Superquadric, GeneralKernelStaysDefinedAtTheLimits) {
  const double powers[][2] = {{1, 16}, {16, 1}, {3, 2.5}, {1, 1}, {16, 16}};
  const fx::Len extents[][3] = {{1, 1, INT32_MAX},
                                {INT32_MAX, 1, 1},
                                {1, INT32_MAX, INT32_MAX},
                                {INT32_MAX, INT32_MAX, INT32_MAX},
                                {1 << 10, 1 << 10, INT32_MAX},
                                {1 << 10, INT32_MAX, 64}};
  const fx::Vec3 points[] = {{0, 0, 0},
                             {0, 0, 1 << 30},
                             {0, 0, -(1 << 30)},
                             {0, 0, INT32_MAX - 1},
                             {1 << 9, 1 << 9, 0},
                             {-(1 << 9), 20, -(1 << 29)},
                             {31, -31, 1 << 20},
                             {INT32_MIN, INT32_MAX, 0},
                             {1, 0, 0}};
  int pushed = 0;
  for (const auto& pw : powers)
    for (const auto& e : extents) {
      muscle::PrimitiveFrame f;
      f.kind = static_cast<uint8_t>(muscle::PrimitiveKind::kSuperellipsoid);
      f.exponent = 0;
      f.active = 1;
      f.axis[0] = {fx::kUnitOne, 0, 0};
      f.axis[1] = {0, fx::kUnitOne, 0};
      f.axis[2] = {0, 0, fx::kUnitOne};
      for (int c = 0; c < 3; ++c) f.extent[c] = e[c];
      f.superquadric.power_xy = static_cast<int32_t>(pw[0] * 65536);
      f.superquadric.power_z = static_cast<int32_t>(pw[1] * 65536);
      muscle::superquadric_prepare(&f);
      for (const fx::Vec3& p : points) {
        const muscle::PrimitiveSample s = muscle::primitive_sample(f, p);
        if (s.inside && !(s.normal == fx::Vec3{0, 0, 0})) {
          const double n2 = static_cast<double>(fx::dot_wide(s.normal, s.normal)) * kU * kU;
          EXPECT_NEAR(n2, 1.0, 1e-6);
        }
        const fx::Vec3 out = muscle::primitive_push_out(f, p, {0, 0, fx::kUnitOne}, 8);
        if (s.inside && !(out == p)) {
          ++pushed;
          // Saturated coordinates can pin a point at the Len range's edge.
          const bool pinned = out.x == INT32_MAX || out.x == INT32_MIN || out.y == INT32_MAX || out.y == INT32_MIN ||
                              out.z == INT32_MAX || out.z == INT32_MIN;
          if (!pinned) EXPECT_FALSE(muscle::primitive_sample(f, out).inside) << pw[0] << "/" << pw[1];
        }
      }
    }
  EXPECT_GT(pushed, 20);
}
