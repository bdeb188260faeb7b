// Barr's global deformations of the primitives (LEMAN §5.2, §6.11; Barr 84):
// the fixed-point inside test, gradient and push-out against a double
// oracle of Barr's taper, twist and bend (the forward map only: its inverse
// and Jacobian are taken numerically here, not from the kernel's formulas),
// and a skin that stays outside a deformed primitive after every step.
#include "sim_core/muscle/primitive_deform.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "dynamic_skin_fixture.hpp"
#include "sim_core/muscle/primitive.hpp"

namespace muscle = sinew::muscle;
namespace fx = sinew::fx;
using sinew::test::DynamicSkin;

namespace {

constexpr double kDeformLsb = 1.0 / (1 << 20);
constexpr double kTurn = 4294967296.0;
constexpr double kPi = 3.141592653589793;

struct Shape {
  muscle::PrimitiveKind kind;
  int exponent;
  double extent[3];
  double taper, twist_deg, bend_deg;
};

muscle::PrimitiveFrame deformed_frame(const Shape& s) {
  muscle::PrimitiveFrame f;
  f.kind = static_cast<uint8_t>(s.kind);
  f.exponent = static_cast<uint8_t>(s.exponent);
  f.active = 1;
  f.centre = {1 << 20, -(2 << 20), 3 << 19};
  // Axes: local x -> world y, y -> -x, z -> z.
  f.axis[0] = {0, fx::kUnitOne, 0};
  f.axis[1] = {-fx::kUnitOne, 0, 0};
  f.axis[2] = {0, 0, fx::kUnitOne};
  for (int i = 0; i < 3; ++i) f.extent[i] = static_cast<fx::Len>(std::llround(s.extent[i] / kDeformLsb));
  f.deformation.taper = static_cast<fx::Unit>(std::llround(s.taper * 1073741824.0));
  f.deformation.twist = static_cast<int32_t>(std::llround(s.twist_deg / 360.0 * kTurn));
  f.deformation.bend = static_cast<int32_t>(std::llround(s.bend_deg / 360.0 * kTurn));
  return f;
}

// Barr's forward map in double, local coordinates (units); the parameters
// read back from the frame so oracle and kernel share them exactly.
void barr_forward(const muscle::PrimitiveFrame& f, const double p[3], double out[3]) {
  const double c = f.extent[2] * kDeformLsb;
  const double taper = f.deformation.taper / 1073741824.0;
  const double twist = f.deformation.twist / kTurn * 2 * kPi, bend = f.deformation.bend / kTurn * 2 * kPi;
  const double zh = std::clamp(p[2], -c, c);
  const double r = 1 + taper * zh / c;
  double x = r * p[0], y = r * p[1];
  const double tw = twist * zh / c;
  const double x2 = x * std::cos(tw) - y * std::sin(tw), y2 = x * std::sin(tw) + y * std::cos(tw);
  x = x2, y = y2;
  out[1] = y;
  if (bend == 0) {
    out[0] = x, out[2] = p[2];
    return;
  }
  const double radius = c / bend, th = bend * zh / c;
  out[0] = radius + std::cos(th) * (x - radius) + std::sin(th) * (p[2] - zh);
  out[2] = -std::sin(th) * (x - radius) + std::cos(th) * (p[2] - zh);
}

double undeformed_f(const muscle::PrimitiveFrame& f, const double p[3]) {
  const bool cyl = f.kind == static_cast<uint8_t>(muscle::PrimitiveKind::kCylinder);
  const int e = f.kind == static_cast<uint8_t>(muscle::PrimitiveKind::kSuperellipsoid) ? f.exponent : 2;
  if (cyl && std::fabs(p[2]) >= f.extent[2] * kDeformLsb) return 4;
  double sum = 0;
  for (int i = 0; i < (cyl ? 2 : 3); ++i) sum += std::pow(std::fabs(p[i] / (f.extent[i] * kDeformLsb)), e);
  return sum;
}

// Jacobian of the forward map by central differences.
void forward_jacobian(const muscle::PrimitiveFrame& f, const double p[3], double j[3][3]) {
  const double h = 1e-6;
  for (int c = 0; c < 3; ++c) {
    double a[3] = {p[0], p[1], p[2]}, b[3] = {p[0], p[1], p[2]}, fa[3], fb[3];
    a[c] += h, b[c] -= h;
    barr_forward(f, a, fa);
    barr_forward(f, b, fb);
    for (int r = 0; r < 3; ++r) j[r][c] = (fa[r] - fb[r]) / (2 * h);
  }
}

bool solve3(const double m[3][3], const double rhs[3], double x[3]) {
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  if (std::fabs(det) < 1e-12) return false;
  for (int c = 0; c < 3; ++c) {
    double t[3][3];
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) t[r][k] = k == c ? rhs[r] : m[r][k];
    x[c] = (t[0][0] * (t[1][1] * t[2][2] - t[1][2] * t[2][1]) - t[0][1] * (t[1][0] * t[2][2] - t[1][2] * t[2][0]) +
            t[0][2] * (t[1][0] * t[2][1] - t[1][1] * t[2][0])) /
           det;
  }
  return true;
}

// D^-1 by Newton on the forward map, from `guess`.
bool barr_inverse(const muscle::PrimitiveFrame& f, const double target[3], const double guess[3], double p[3]) {
  for (int i = 0; i < 3; ++i) p[i] = guess[i];
  for (int it = 0; it < 50; ++it) {
    double q[3], j[3][3], step[3];
    barr_forward(f, p, q);
    const double r[3] = {target[0] - q[0], target[1] - q[1], target[2] - q[2]};
    if (std::fabs(r[0]) + std::fabs(r[1]) + std::fabs(r[2]) < 1e-13) return true;
    forward_jacobian(f, p, j);
    if (!solve3(j, r, step)) return false;
    for (int i = 0; i < 3; ++i) p[i] += step[i];
  }
  return false;
}

// Local (units) -> world Len point of the frame above, and back.
fx::Vec3 local_to_world(const muscle::PrimitiveFrame& f, const double l[3]) {
  return {f.centre.x + static_cast<int32_t>(std::llround(-l[1] / kDeformLsb)),
          f.centre.y + static_cast<int32_t>(std::llround(l[0] / kDeformLsb)),
          f.centre.z + static_cast<int32_t>(std::llround(l[2] / kDeformLsb))};
}
void world_to_local(const muscle::PrimitiveFrame& f, fx::Vec3 p, double l[3]) {
  l[0] = (p.y - f.centre.y) * kDeformLsb;
  l[1] = -(p.x - f.centre.x) * kDeformLsb;
  l[2] = (p.z - f.centre.z) * kDeformLsb;
}

const Shape kShapes[] = {
    {muscle::PrimitiveKind::kSuperellipsoid, 4, {0.3, 0.2, 0.9}, 0.3, 0, 0},
    {muscle::PrimitiveKind::kSuperellipsoid, 4, {0.3, 0.2, 0.9}, 0, 60, 0},
    {muscle::PrimitiveKind::kSuperellipsoid, 4, {0.3, 0.2, 0.9}, 0, 0, 30},
    {muscle::PrimitiveKind::kSuperellipsoid, 2, {0.25, 0.15, 1.0}, -0.4, -45, -25},
    {muscle::PrimitiveKind::kSuperellipsoid, 8, {0.2, 0.3, 0.8}, 0.2, 30, 20},
    {muscle::PrimitiveKind::kCylinder, 2, {0.15, 0.1, 0.7}, 0.5, 90, 40},
    {muscle::PrimitiveKind::kSphere, 2, {0.4, 0.4, 0.4}, -0.3, 20, 0},
};

}  // namespace

TEST(PrimitiveDeform, InsideTestAndGradientMatchBarrsFormulasInDouble) {
  for (const Shape& shape : kShapes) {
    const muscle::PrimitiveFrame f = deformed_frame(shape);
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u(-1.25, 1.25);
    int inside = 0, mismatched = 0, undeformed_disagree = 0, tested = 0;
    double worst_value = 0, worst_angle = 0;
    for (int i = 0; i < 20000; ++i) {
      // Undeformed points around the primitive, mapped by the oracle.
      double p0[3] = {u(rng) * shape.extent[0], u(rng) * shape.extent[1], u(rng) * shape.extent[2]};
      double p3[3];
      barr_forward(f, p0, p3);
      const fx::Vec3 world = local_to_world(f, p3);
      // The oracle sees the quantised point the kernel sees.
      double q3[3], q0[3];
      world_to_local(f, world, q3);
      if (!barr_inverse(f, q3, p0, q0)) continue;
      const double want = undeformed_f(f, q0);
      const muscle::PrimitiveSample s = muscle::primitive_sample(f, world);
      ++tested;
      mismatched += (s.inside != (want < 1)) && std::fabs(want - 1) > 1e-4;
      inside += s.inside;
      // The same point against the undeformed primitive: the deformation matters.
      muscle::PrimitiveFrame plain = f;
      plain.deformation = {};
      undeformed_disagree += muscle::primitive_sample(plain, world).inside != (want < 1);
      // Deep inside (F < 0.05: within a fifth of the extents of the centre
      // or axis) the direction rests on a few LSB of position; skin points
      // reach a primitive from outside, where it is well conditioned.
      if (want >= 1 || want < 0.05) continue;
      worst_value = std::max(worst_value, std::fabs(std::ldexp(static_cast<double>(s.value), -30) - want));
      // Gradient of F o D^-1: the covariant J^-T grad F (numerical J).
      double g0[3];
      for (int c = 0; c < 3; ++c) {
        double a[3] = {q0[0], q0[1], q0[2]}, b[3] = {q0[0], q0[1], q0[2]};
        a[c] += 1e-7, b[c] -= 1e-7;
        g0[c] = (undeformed_f(f, a) - undeformed_f(f, b)) / 2e-7;
      }
      double j[3][3], jt[3][3], g3[3];
      forward_jacobian(f, q0, j);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) jt[r][c] = j[c][r];
      if (!solve3(jt, g0, g3)) continue;
      const double gn = std::sqrt(g3[0] * g3[0] + g3[1] * g3[1] + g3[2] * g3[2]);
      if (gn < 1e-2) continue;  // near the centre the direction is undefined
      // World normal -> local: local x = world y, local y = -world x.
      const double n[3] = {std::ldexp(s.normal.y, -30), -std::ldexp(s.normal.x, -30), std::ldexp(s.normal.z, -30)};
      const double cosang = (g3[0] * n[0] + g3[1] * n[1] + g3[2] * n[2]) / gn;
      worst_angle = std::max(worst_angle, std::acos(std::min(1.0, cosang)));
    }
    std::printf(
        "kind %d p=%d taper %.2f twist %.0f bend %.0f: %d inside of %d, %d differ from the undeformed test, worst "
        "|F - oracle| %.3g, worst gradient angle %.3g rad\n",
        shape.kind == muscle::PrimitiveKind::kCylinder ? 1 : (shape.kind == muscle::PrimitiveKind::kSphere ? 0 : 2),
        shape.exponent, shape.taper, shape.twist_deg, shape.bend_deg, inside, tested, undeformed_disagree, worst_value,
        worst_angle);
    EXPECT_GT(tested, 19000);
    EXPECT_EQ(mismatched, 0);
    EXPECT_GT(undeformed_disagree, 500) << "the deformation changes the shape noticeably";
    EXPECT_GT(inside, 2000);
    // F at the same quantised point: the inverse map's rounding (a few LSB
    // of position, 1e-5 units here) moves F by |grad F| * 1e-5 < 1e-3.
    EXPECT_LT(worst_value, 1e-3);
    // Direction: Q2.30 trig and narrowed gradients, far below a milliradian.
    EXPECT_LT(worst_angle, 1e-3);
  }
}

TEST(PrimitiveDeform, PushOutLandsOnTheDeformedSurface) {
  // Newton runs on the undeformed point and its landing point is mapped
  // forward: the deformed push-out is D o N o D^-1 with N the undeformed
  // kernel's push-out. So from the kernel's own undeformed start (its
  // primitive_undeform of the same point), N lands at some p0', and the
  // deformed kernel's output, mapped back by Barr's exact inverse, must be
  // p0' up to the forward map's rounding: taper 0.5 LSB, twist and bend
  // 1 LSB each per axis (two Q2.30 products each; their trig and angle
  // roundings times extents below 2^20 LSB add < 0.01 LSB), so 3 LSB per
  // axis, through |J^-1| back to the undeformed frame. Whatever N's
  // overshoot on elongated shapes (primitive_test.cpp), the deformation
  // adds nothing to it. Checked on shallow points (F >= 0.5, skin reaching
  // the primitive from outside).
  for (const Shape& shape : kShapes) {
    const muscle::PrimitiveFrame f = deformed_frame(shape);
    muscle::PrimitiveFrame plain = f;
    plain.deformation = {};
    plain.centre = {0, 0, 0};
    plain.axis[0] = {fx::kUnitOne, 0, 0};
    plain.axis[1] = {0, fx::kUnitOne, 0};
    plain.axis[2] = {0, 0, fx::kUnitOne};
    const bool cyl = shape.kind == muscle::PrimitiveKind::kCylinder;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int tried = 0, still_inside = 0, shallow = 0;
    double worst_deformed = 0, worst_ratio = 0;
    for (int i = 0; i < 3000; ++i) {
      double p0[3] = {u(rng) * shape.extent[0], u(rng) * shape.extent[1], u(rng) * shape.extent[2]};
      const double before = undeformed_f(f, p0);
      if (before >= 1) continue;
      double p3[3];
      barr_forward(f, p0, p3);
      const fx::Vec3 world = local_to_world(f, p3);
      ++tried;
      const fx::Vec3 out = muscle::primitive_push_out(f, world, {0, 0, fx::kUnitOne}, 3);
      double l3[3], l0[3];
      world_to_local(f, out, l3);
      ASSERT_TRUE(barr_inverse(f, l3, p0, l0));
      const double after = undeformed_f(f, l0);
      still_inside += after < 1 - 1.0 / 1024;
      if (before < 0.5) continue;
      ++shallow;
      worst_deformed = std::max(worst_deformed, after - 1);
      // The kernel's start: the world point in the frame (exact on these
      // axes), mapped back by the kernel's inverse; N from there.
      const int64_t local[3] = {world.y - f.centre.y, -(int64_t{world.x} - f.centre.x), world.z - f.centre.z};
      muscle::DeformTrace trace;
      ASSERT_TRUE(muscle::primitive_undeform(f, local, &trace));
      const fx::Vec3 start{static_cast<int32_t>(trace.undeformed[0]), static_cast<int32_t>(trace.undeformed[1]),
                           static_cast<int32_t>(trace.undeformed[2])};
      const fx::Vec3 landed = muscle::primitive_push_out(plain, start, {0, 0, fx::kUnitOne}, 3);
      const double q[3] = {landed.x * kDeformLsb, landed.y * kDeformLsb, landed.z * kDeformLsb};
      // |grad F| at the landing point and |J^-1| there (Frobenius norm,
      // from the oracle's numerical Jacobian).
      double grad = 0;
      for (int c = 0; c < (cyl ? 2 : 3); ++c) {
        const double a = shape.extent[c] * 1.0, t = q[c] / a;
        grad += std::pow(shape.exponent * std::pow(std::fabs(t), shape.exponent - 1) / a, 2);
      }
      double j[3][3], inv_norm = 0;
      forward_jacobian(f, q, j);
      for (int c = 0; c < 3; ++c) {
        const double unit[3] = {c == 0 ? 1.0 : 0.0, c == 1 ? 1.0 : 0.0, c == 2 ? 1.0 : 0.0};
        double col[3];
        ASSERT_TRUE(solve3(j, unit, col));
        inv_norm += col[0] * col[0] + col[1] * col[1] + col[2] * col[2];
      }
      const double bound = std::sqrt(grad) * std::sqrt(inv_norm) * 3 * std::sqrt(3.0) * kDeformLsb;
      worst_ratio = std::max(worst_ratio, std::fabs(after - undeformed_f(f, q)) / bound);
    }
    std::printf(
        "push-out: %d inside, %d still inside beyond 2^-10, worst shallow F - 1 %.3g (%d points); against the "
        "undeformed kernel from its own start: %.3f of the forward map's rounding bound\n",
        tried, still_inside, worst_deformed, shallow, worst_ratio);
    EXPECT_GT(tried, 200);
    EXPECT_EQ(still_inside, 0);
    EXPECT_LE(worst_ratio, 1.0);
  }
}

TEST(PrimitiveDeform, NoSkinPointInsideADeformedPrimitiveAfterAStep) {
  // A cylinder along z (radius 0.1, half height 0.5) bent by 40 degrees at
  // each end: its axis reaches x = R (1 - cos 40) = 0.168 at the caps.
  // Skin points on the line x = 0.15 lie inside the bent cylinder near the
  // ends and outside the straight one everywhere: a kernel that ignored
  // the bend would leave them inside.
  for (const uint8_t mode : {uint8_t{0}, uint8_t{1}}) {
    DynamicSkin s;
    s.model.solver.mode = mode;
    constexpr int kPoints = 19;
    for (int i = 0; i < kPoints; ++i) s.add_vertex(0.15, 0.0, -0.45 + 0.05 * i, 1.0);
    for (int i = 0; i + 1 < kPoints; ++i) s.add_edge(static_cast<uint32_t>(i), static_cast<uint32_t>(i + 1), 0.5, 0.05);
    s.add_sphere(0, 0, 0, 0.1);
    muscle::PrimitiveFrame& f = s.frames.back();
    f.kind = static_cast<uint8_t>(muscle::PrimitiveKind::kCylinder);
    f.extent[2] = sinew::test::to_len(0.5);
    f.deformation.bend = static_cast<int32_t>(std::llround(40.0 / 360.0 * kTurn));
    ASSERT_TRUE(s.finish());
    const double c = 0.5;
    int inside_bent = 0;
    for (int i = 0; i < kPoints; ++i) {
      const double p[3] = {0.15, 0.0, -0.45 + 0.05 * i}, guess[3] = {0, 0, p[2]};
      double p0[3];
      if (barr_inverse(f, p, guess, p0) && undeformed_f(f, p0) < 1) ++inside_bent;
      EXPECT_GE(std::hypot(p[0], p[1]), 0.1);  // outside the straight cylinder
    }
    ASSERT_GT(inside_bent, 2) << "the scene must put anchors inside the bent shape";
    for (int k = 0; k < 50; ++k) {
      s.move_bone(0.0, 0.0, 0.02 * std::sin(k * 0.2));
      ASSERT_TRUE(s.step(1000).ok());
      EXPECT_EQ(s.state.stats.inside_after, 0u) << "mode " << int{mode} << " tick " << k;
      for (uint32_t v = 0; v < s.model.vertex_count; ++v) {
        const double p[3] = {s.pos(0, v), s.pos(1, v), s.pos(2, v)}, guess[3] = {0, 0, std::clamp(p[2], -c, c)};
        double p0[3];
        ASSERT_TRUE(barr_inverse(f, p, guess, p0));
        ASSERT_GE(undeformed_f(f, p0), 1.0 - 1.0 / 1024) << "mode " << int{mode} << " tick " << k << " vertex " << v;
      }
    }
    std::printf("mode %d: %d of %d anchors inside the bent cylinder, all skin points outside after every step\n",
                int{mode}, inside_bent, kPoints);
  }
}
