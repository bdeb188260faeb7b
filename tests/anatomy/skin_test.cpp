// Elastic skin over the arm's bones and muscles: anchors at rest, the
// relaxation's convergence, reaction constraints, the visible bulge.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "anatomy_fixture.hpp"

using sinew::test::ArmAnatomy;
namespace ab = sinew::anatomy_build;
namespace es = sinew::elastic_skin;
namespace muscle = sinew::muscle;

namespace {

// Largest y of the skin over the biceps belly (rest x in [0.12, 0.20] m,
// |z| < 1 cm): the upper arm stays put when only the elbow moves.
double belly_height(ArmAnatomy& arm, bool relaxed) {
  double top = -1;
  for (uint32_t v = 0; v < arm.rig().vertex_count(); ++v) {
    const auto& rest = arm.spec().vertices[v].position;
    if (rest[0] < 0.12 || rest[0] > 0.20 || std::fabs(rest[2]) > 0.01 || rest[1] < 0) continue;
    const double y = relaxed ? arm.skin_pos(1, v) : arm.metres(arm.engine().vertices.position[1][v]);
    top = std::max(top, y);
  }
  return top;
}

// F of a placed primitive at a point, in double: an oracle independent of
// the fixed-point kernel (superellipsoids only, as the arm uses).
double inside_function(ArmAnatomy& arm, const muscle::PrimitiveFrame& f, const double p[3]) {
  const double c[3] = {arm.metres(f.centre.x), arm.metres(f.centre.y), arm.metres(f.centre.z)};
  double sum = 0;
  for (int i = 0; i < 3; ++i) {
    const sinew::fx::Vec3 ax = f.axis[i];
    const double local = (p[0] - c[0]) * std::ldexp(ax.x, -30) + (p[1] - c[1]) * std::ldexp(ax.y, -30) +
                         (p[2] - c[2]) * std::ldexp(ax.z, -30);
    const double q = std::fabs(local / arm.metres(f.extent[i]));
    double qp = 1;
    for (int k = 0; k < f.exponent; ++k) qp *= q;
    sum += qp;
  }
  return sum;
}

}  // namespace

TEST(ElasticSkin, VirtualAnchorsMapBackToTheRestSkinAtRest) {
  ArmAnatomy arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  const ab::BuildReport& r = arm.model().report;
  std::printf(
      "anchoring: %u muscle anchors, %u bone anchors, %u edges, %u rubber bands, mean edge %.2f mm, "
      "worst Newton residual %.3g m\n",
      r.muscle_anchors, r.bone_anchors, r.edges, r.bands, r.mean_edge_length * 1e3, r.max_newton_residual);
  ASSERT_TRUE(arm.step().ok());
  double worst = 0;
  for (uint32_t v = 0; v < arm.rig().vertex_count(); ++v)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::fabs(arm.metres(arm.skin().anchor[c][v]) -
                                        arm.spec().vertices[v].position[static_cast<size_t>(c)]));
  std::printf(
      "rest pose: virtual anchors vs rest skin, worst %.3g m (builder's check %.3g m; stated tolerance 1e-6 m)\n",
      worst, r.max_rest_anchor_error);
  EXPECT_GT(r.muscle_anchors, 200u);
  EXPECT_GT(r.bone_anchors, 200u);
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(r.max_rest_anchor_error, 1e-6);
}

TEST(ElasticSkin, LargestRelaxationVectorShrinksWithIterations) {
  ArmAnatomy arm([](ab::AnatomySpec& s) { s.skin.iterations = 60; });
  ASSERT_TRUE(arm.ok()) << arm.error();
  arm.set("elbow.0", 100);
  arm.set("shoulder.0", 30);
  ASSERT_TRUE(arm.step().ok());
  const auto mm = [&](uint32_t i) { return arm.metres(arm.skin().max_relax[i]) * 1e3; };
  std::printf("largest relaxation vector (mm) by iteration, elbow 100 deg:");
  for (uint32_t i : {0u, 1u, 2u, 4u, 9u, 19u, 29u, 39u, 59u}) std::printf(" [%u] %.4f", i + 1, mm(i));
  std::printf("\n");
  const double ratio30 = mm(29) / mm(0);
  std::printf("iteration 30 / iteration 1: %.4f; iteration 60 / iteration 30: %.4f\n", ratio30, mm(59) / mm(29));
  EXPECT_GT(mm(0), 0.0);
  EXPECT_LT(ratio30, 0.2) << "close to equilibrium after about 30 relaxations";
  EXPECT_LE(mm(59), mm(29));
}

TEST(ElasticSkin, NoSkinPointInsideAnActivePrimitiveAfterAStep) {
  ArmAnatomy arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  for (int a : {0, 60, 120, 150}) {
    arm.set("elbow.0", a);
    arm.set("shoulder.1", a / 5.0);
    ASSERT_TRUE(arm.step().ok());
    double deepest = 10;
    for (uint32_t v = 0; v < arm.rig().vertex_count(); ++v) {
      const double n[3] = {std::ldexp(arm.skin().normal[0][v], -30), std::ldexp(arm.skin().normal[1][v], -30),
                           std::ldexp(arm.skin().normal[2][v], -30)};
      const double fat = arm.metres(arm.skin_model().fat[v]);
      const double p[3] = {arm.skin_pos(0, v) - fat * n[0], arm.skin_pos(1, v) - fat * n[1],
                           arm.skin_pos(2, v) - fat * n[2]};
      for (const muscle::PrimitiveFrame& f : arm.muscles().primitives)
        if (f.active) deepest = std::min(deepest, inside_function(arm, f, p));
    }
    std::printf("elbow %3d deg: reactions %u, collisions %u, fat points inside after the step %u, smallest F %.6f\n", a,
                arm.skin().stats.reactions, arm.skin().stats.collisions, arm.skin().stats.inside_after, deepest);
    EXPECT_EQ(arm.skin().stats.inside_after, 0u);
    EXPECT_GT(deepest, 1.0 - 1.0 / 512) << "inside/outside function below 1 beyond the tolerance";
  }
}

TEST(ElasticSkin, BicepsBulgeRaisesTheSkinWithFlexion) {
  ArmAnatomy arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  double previous = -1, first = 0, last = 0, skinned_last = 0;
  for (int a = 0; a <= 150; a += 50) {
    arm.set("elbow.0", a);
    ASSERT_TRUE(arm.step().ok());
    const double h = belly_height(arm, true), lbs = belly_height(arm, false);
    std::printf("elbow %3d deg: skin height over the biceps %.2f mm (skinning alone %.2f mm)\n", a, h * 1e3, lbs * 1e3);
    EXPECT_GE(h, previous - 1e-5);
    if (a == 0) first = h;
    previous = last = h;
    skinned_last = lbs;
  }
  std::printf("bulge at 150 deg: +%.2f mm over rest (skinning alone: %+.2f mm)\n", (last - first) * 1e3,
              (skinned_last - first) * 1e3);
  EXPECT_GT(last - first, 0.002) << "at least 2 mm of visible bulge at full flexion";
}
