// The elastic skin (static relaxation and LEMAN §3's dynamic mode) against
// a general superquadric primitive (p_xy = 3, p_z = 2.5: only the general
// kernel handles it), and the arm's steps with its muscles' bellies made
// general: no fat point left inside, no heap allocation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dynamic_skin_fixture.hpp"
#include "sim_core/muscle/superquadric.hpp"
#include "tests/sim_core/muscle/anatomy_fixture.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/soak.hpp"

using sinew::test::DynamicSkin;
namespace muscle = sinew::muscle;
namespace fx = sinew::fx;

namespace {

constexpr double kSkinSqA = 0.2, kSkinSqB = 0.16, kSkinSqC = 0.2;  // half-extents, units
constexpr double kSkinSqPxy = 3.0, kSkinSqPz = 2.5;
constexpr double kSkinSqFat = 0.02;

// An active general superquadric at the origin, identity axes.
void add_superquadric(DynamicSkin& s) {
  muscle::PrimitiveFrame f;
  f.axis[0] = {fx::kUnitOne, 0, 0};
  f.axis[1] = {0, fx::kUnitOne, 0};
  f.axis[2] = {0, 0, fx::kUnitOne};
  f.extent[0] = sinew::test::to_len(kSkinSqA);
  f.extent[1] = sinew::test::to_len(kSkinSqB);
  f.extent[2] = sinew::test::to_len(kSkinSqC);
  f.kind = static_cast<uint8_t>(muscle::PrimitiveKind::kSuperellipsoid);
  f.exponent = 0;
  f.active = 1;
  f.superquadric.power_xy = static_cast<int32_t>(kSkinSqPxy * 65536);
  f.superquadric.power_z = static_cast<int32_t>(kSkinSqPz * 65536);
  muscle::superquadric_prepare(&f);
  s.frames.push_back(f);
  s.primitive_records.emplace_back();
}

// Barr's F in double at a point (units).
double skin_sq_f(double x, double y, double z) {
  const double s = std::pow(std::fabs(x / kSkinSqA), kSkinSqPxy) + std::pow(std::fabs(y / kSkinSqB), kSkinSqPxy);
  return std::pow(s, kSkinSqPz / kSkinSqPxy) + std::pow(std::fabs(z / kSkinSqC), kSkinSqPz);
}

// Two rings of skin round the primitive (one in the xy plane, one in the xz
// plane: both exponents matter), radius 0.25, fat 0.02, linked by edges.
void add_rings(DynamicSkin& s) {
  constexpr int kCount = 16;
  for (int ring = 0; ring < 2; ++ring) {
    const uint32_t first = static_cast<uint32_t>(s.anchors.size());
    for (int i = 0; i < kCount; ++i) {
      const double a = 2 * 3.141592653589793 * i / kCount;
      const double u = 0.25 * std::cos(a), v = 0.25 * std::sin(a);
      if (ring == 0) {
        s.add_vertex(u, v, 0, 2.0, kSkinSqFat);
      } else {
        s.add_vertex(u, 0, v, 2.0, kSkinSqFat);
      }
    }
    for (int i = 0; i < kCount; ++i)
      s.add_edge(first + static_cast<uint32_t>(i), first + static_cast<uint32_t>((i + 1) % kCount), 1.0, 0.0975);
  }
}

// Drives the bone 0.15 into the primitive and back for `ticks` ticks; after
// every step checks the skin's own count and every fat point against
// Barr's F. The bound: the step leaves F_kernel >= 1 - 2^-10 (its inside
// test); Barr's F is at most the kernel's F bound below that
// (superquadric.hpp: [ln 2 (p_z + e + 1/2) + 1.01] 2^-30 at F = 1), and the fat
// point formed here in double differs from the kernel's fixed-point one by
// at most the Len rounding of its three components (sqrt(3) LSB) times
// |grad F| <= sqrt(3) p_z / min extent (superquadric.hpp).
uint32_t run_skin(DynamicSkin& s, int ticks, double* lowest) {
  const double lsb = 1.0 / 1048576.0, e = kSkinSqPz / kSkinSqPxy;
  const double bound = std::ldexp(1.0, -10) + (0.6931471805599453 * (kSkinSqPz + e + 0.5) + 1.01) / 1073741824.0 +
                       std::sqrt(3.0) * lsb * std::sqrt(3.0) * kSkinSqPz / std::min({kSkinSqA, kSkinSqB, kSkinSqC});
  uint32_t pushed = 0;
  *lowest = 2;
  for (int k = 0; k < ticks; ++k) {
    s.move_bone(0.15 * std::sin(k * 0.05), 0, 0);
    EXPECT_TRUE(s.step(1000).ok());
    pushed += s.state.stats.reactions;
    EXPECT_EQ(s.state.stats.inside_after, 0u) << "tick " << k;
    for (uint32_t v = 0; v < s.model.vertex_count; ++v) {
      const double n[3] = {s.state.normal[0][v] / 1073741824.0, s.state.normal[1][v] / 1073741824.0,
                           s.state.normal[2][v] / 1073741824.0};
      const double f =
          skin_sq_f(s.pos(0, v) - kSkinSqFat * n[0], s.pos(1, v) - kSkinSqFat * n[1], s.pos(2, v) - kSkinSqFat * n[2]);
      *lowest = std::min(*lowest, f);
      EXPECT_GE(f, 1 - bound) << "tick " << k << " vertex " << v;
    }
  }
  return pushed;
}

}  // namespace

TEST(SuperquadricSkin, NoFatPointInsideAfterADynamicStep) {
  DynamicSkin s;
  add_rings(s);
  add_superquadric(s);
  s.model.solver.gravity = {0, sinew::test::to_accel(-9.81), 0};
  ASSERT_TRUE(s.finish());
  double lowest = 0;
  const uint32_t pushed = run_skin(s, 300, &lowest);
  std::printf("dynamic skin around p_xy 3, p_z 2.5: %u reactions, lowest Barr F of a fat point %.9f\n", pushed, lowest);
  EXPECT_GT(pushed, 100u);  // the constraint did work
}

TEST(SuperquadricSkin, NoFatPointInsideAfterAStaticStep) {
  DynamicSkin s;
  s.model.solver.mode = static_cast<uint8_t>(sinew::elastic_skin::SkinMode::kStatic);
  s.model.params.iterations = 4;
  add_rings(s);
  add_superquadric(s);
  ASSERT_TRUE(s.finish());
  double lowest = 0;
  const uint32_t pushed = run_skin(s, 120, &lowest);
  std::printf("static skin around p_xy 3, p_z 2.5: %u reactions, lowest Barr F of a fat point %.9f\n", pushed, lowest);
  EXPECT_GT(pushed, 100u);
}

// Barr's dF/dx (units^-1) in double.
void skin_sq_gradient(const double x[3], double g[3]) {
  const double ext[3] = {kSkinSqA, kSkinSqB, kSkinSqC};
  double q[3], sign[3];
  for (int i = 0; i < 3; ++i) {
    q[i] = std::fabs(x[i] / ext[i]);
    sign[i] = (x[i] > 0) - (x[i] < 0);
  }
  const double s = std::pow(q[0], kSkinSqPxy) + std::pow(q[1], kSkinSqPxy), e = kSkinSqPz / kSkinSqPxy;
  for (int i = 0; i < 2; ++i)
    g[i] = q[i] > 0 ? kSkinSqPz * std::pow(s, e - 1) * std::pow(q[i], kSkinSqPxy - 1) * sign[i] / ext[i] : 0;
  g[2] = q[2] > 0 ? kSkinSqPz * std::pow(q[2], kSkinSqPz - 1) * sign[2] / ext[2] : 0;
}

// The static relaxation with lone vertices (anchor springs only, no
// edges): every round moves a vertex onto its anchor, and the last round's
// reaction pass pushes its fat point out with newton_steps Newton steps on
// G = F^(1/p_z) along grad G (superquadric.hpp). So the skin must end where
// Barr's own Newton steps from the anchor's fat point land, in double. The
// tolerance (Len LSB = 2^-20 units): the start may differ by the anchor
// relaxation's rounding (sqrt(3) LSB, moving the landing as much); each
// kernel step adds its 1 LSB nudge and sqrt(3)/2 of Len rounding, and its
// length and direction are off by (rho + theta) of it, rho, theta < 1e-7
// for these exponents (superquadric_test.cpp's bounds: at most 3.3e-8 and
// 1.6e-8 here, plus u / (1 - G) with 1 - G >= 1/2).
TEST(SuperquadricSkin, StaticSkinRestsWhereBarrsNewtonStepsLand) {
  DynamicSkin s;
  s.model.solver.mode = static_cast<uint8_t>(sinew::elastic_skin::SkinMode::kStatic);
  s.model.params.iterations = 6;
  const double dirs[][3] = {{1, 1, 0},  {1, -2, 0}, {-3, 1, 0},  {1, 0, 1},
                            {-1, 0, 2}, {1, 1, 1},  {-2, 1, -1}, {0, 1, 0}};
  for (const auto& d : dirs) {
    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    s.add_vertex(0.08 * d[0] / n, 0.08 * d[1] / n, 0.08 * d[2] / n, 2.0, kSkinSqFat);
  }
  add_superquadric(s);
  ASSERT_TRUE(s.finish());
  ASSERT_TRUE(s.step(1000).ok());
  EXPECT_EQ(s.state.stats.inside_after, 0u);
  const double lsb = 1.0 / 1048576.0;
  const double tolerance = (2 * std::sqrt(3.0) + 3 * (1 + std::sqrt(3.0) / 2)) * lsb + 3 * 0.2 * 1e-7;
  double worst = 0;
  for (uint32_t v = 0; v < s.model.vertex_count; ++v) {
    const fx::Vec3 n{s.state.normal[0][v], s.state.normal[1][v], s.state.normal[2][v]};
    const fx::Len fat = sinew::test::to_len(kSkinSqFat);
    // The kernel's fat point, as the skin forms it (Len).
    const fx::Vec3 anchor = s.anchors[v].local_a;
    const fx::Vec3 off{fx::mul_by_unit(fat, n.x), fx::mul_by_unit(fat, n.y), fx::mul_by_unit(fat, n.z)};
    double x[3] = {(anchor.x - off.x) * lsb, (anchor.y - off.y) * lsb, (anchor.z - off.z) * lsb};
    for (int step = 0; step < 3; ++step) {  // Barr's Newton steps on G
      const double f = skin_sq_f(x[0], x[1], x[2]);
      if (f >= 1) break;
      double g[3];
      skin_sq_gradient(x, g);
      const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
      const double big_g = std::pow(f, 1 / kSkinSqPz), grad_g = big_g / (kSkinSqPz * f) * gn;
      for (int c = 0; c < 3; ++c) x[c] += (1 - big_g) / grad_g * g[c] / gn;
    }
    const double got[3] = {s.pos(0, v) - off.x * lsb, s.pos(1, v) - off.y * lsb, s.pos(2, v) - off.z * lsb};
    const double dist = std::sqrt((got[0] - x[0]) * (got[0] - x[0]) + (got[1] - x[1]) * (got[1] - x[1]) +
                                  (got[2] - x[2]) * (got[2] - x[2]));
    worst = std::max(worst, dist);
    EXPECT_LE(dist, tolerance) << "vertex " << v;
  }
  std::printf(
      "static skin on p_xy 3, p_z 2.5: fat points within %.3g units of Barr's Newton landing (tolerance %.3g)\n", worst,
      tolerance);
}

// The arm with both bellies general superquadrics (MUSC exponents): steps
// never touch the heap (as AnatomyAllocation for the exact kernels).
TEST(SuperquadricSkin, ArmStepsWithGeneralBelliesNeverTouchTheHeap) {
  sinew::test::ArmAnatomy arm([](sinew::anatomy_build::AnatomySpec& s) {
    s.skin.iterations = 2;
    s.skin.warm_start = true;
    for (auto& p : s.primitives) {
      p.exponent = 3;
      p.exponent_z = 2.5;
    }
  });
  ASSERT_TRUE(arm.ok()) << arm.error();
  ASSERT_EQ(arm.muscle_model().exponents.size(), arm.muscle_model().primitives.size());
  for (const auto& r : arm.muscle_model().primitives) EXPECT_EQ(r.exponent, 0);
  const int steps = sinew::test::soak_enabled() ? 100000 : (sinew::test::emulated() ? 100 : 500);
  const size_t elbow = static_cast<size_t>(arm.input("elbow.0")),
               shoulder = static_cast<size_t>(arm.input("shoulder.0"));
  sinew::test::AllocationCounter counter;
  uint32_t failures = 0, reactions = 0, inside = 0;
  for (int k = 0; k < steps; ++k) {
    arm.inputs()[elbow] = sinew::test::deg((k * 7) % 150);
    arm.inputs()[shoulder] = sinew::test::deg((k * 3) % 90 - 45);
    failures += !arm.step().ok();
    reactions += arm.skin().stats.reactions;
    inside += arm.skin().stats.inside_after;
  }
  std::printf("%d arm steps with general bellies (p_xy 3, p_z 2.5): %llu heap allocations, %u reactions\n", steps,
              static_cast<unsigned long long>(counter.allocations()), reactions);
  EXPECT_EQ(failures, 0u);
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_EQ(inside, 0u);
  EXPECT_GT(reactions, 0u);
}
