// Elastic skin over the arm's bones and muscles: anchors at rest, the
// relaxation's convergence, reaction constraints, the visible bulge.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "tests/sim_core/muscle/anatomy_fixture.hpp"

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
  // Each round is Jacobi on eqs. (1)-(2) (RelaxationRoundIsSection52 below):
  // with the springs acting linearly and the constraints settled,
  // x_v <- (sum k_e x_j + k_a anchor_v) / (sum k_e + k_a), an iteration
  // matrix whose rows sum to sum k_e / (sum k_e + k_a) (the paper's
  // "conservatively large" denominator). Each round then shrinks the
  // relaxation vector by at least rho, the largest row sum of this model;
  // "close to equilibrium after about 30 iterations" is 29 rounds of it.
  const es::SkinModel& m = arm.skin_model();
  std::vector<double> edge_sum(m.vertex_count, 0);
  for (const es::Edge& e : m.edges) {
    edge_sum[e.a] += e.k / 65536.0;
    edge_sum[e.b] += e.k / 65536.0;
  }
  double rho = 0;
  for (uint32_t v = 0; v < m.vertex_count; ++v)
    rho = std::max(rho, edge_sum[v] / (edge_sum[v] + m.anchor_stiffness[v] / 65536.0));
  const double ratio30 = mm(29) / mm(0);
  std::printf("iteration 30 / iteration 1: %.4f (bound rho^29 = %.4f, rho %.5f); iteration 60 / iteration 30: %.4f\n",
              ratio30, std::pow(rho, 29), rho, mm(59) / mm(29));
  EXPECT_GT(mm(0), 0.0);
  EXPECT_LT(ratio30, std::pow(rho, 29)) << "close to equilibrium after about 30 relaxations";
  EXPECT_LE(mm(59), mm(29)) << "after 30, changes from one iteration to the next are barely noticeable";
}

TEST(ElasticSkin, RelaxationRoundIsSection52) {
  // One round of §5.2 in double, from the runtime's own positions after the
  // rounds before it: every vertex moves by the net force of its edge springs
  // (eq. 1, weakened by the push-back rule when compressed), rubber bands and
  // anchor spring (eq. 2), over the sum of the stiffnesses that contributed;
  // all forces from the positions at the start of the round. Collision
  // spheres off and primitives inactive: the round is the relaxation alone.
  ArmAnatomy arm([](ab::AnatomySpec& s) {
    s.skin.collision_radius = 0;
    for (ab::PrimitiveSpec& p : s.primitives) p.active = false;
  });
  ASSERT_TRUE(arm.ok()) << arm.error();
  arm.set("elbow.0", 100);
  arm.set("shoulder.0", 30);
  es::SkinModel& m = arm.skin_model();
  const uint32_t n = m.vertex_count;
  using Points = std::vector<std::array<double, 3>>;
  Points before(n);
  m.params.iterations = 1;
  ASSERT_TRUE(arm.step().ok());
  for (uint32_t v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c) before[v][static_cast<size_t>(c)] = arm.skin().anchor[c][v];  // round 1 starts here
  const double pb = m.params.push_back / 1073741824.0, band_ratio = m.params.compression_band / 1073741824.0;
  double worst_ratio = 0, worst_lsb = 0;
  for (uint32_t round = 1; round <= 30; ++round) {
    m.params.iterations = round;  // each step restarts from the anchors: its last round is round `round`
    ASSERT_TRUE(arm.step().ok());
    Points force(n, {0, 0, 0});
    std::vector<double> weight(n, 0), error(n, 0), weight_error(n, 0);
    for (const es::Edge& e : m.edges) {
      double w[3], len2 = 0;
      for (size_t c = 0; c < 3; ++c) {
        w[c] = before[e.b][c] - before[e.a][c];
        len2 += w[c] * w[c];
      }
      const double len = std::sqrt(len2), rest = e.rest, excess = len - rest, band = band_ratio * rest;
      double k = e.k / 65536.0, dk = 0;
      if (excess < 0) {
        k *= -excess >= band ? pb : 1 - (1 - pb) * -excess / band;
        // Q2.30 multiplier from a length one LSB short (its integer root
        // floors) and a band rounded to Len: (1 - pb) 1.5 / band; then k
        // rounded to Q16.16.
        dk = e.k / 65536.0 * ((1 - pb) * 1.5 / band + 0x1p-30) + 0x1p-17;
      }
      if (len == 0) continue;
      for (size_t c = 0; c < 3; ++c) {
        force[e.a][c] += k * excess * w[c] / len;
        force[e.b][c] -= k * excess * w[c] / len;
      }
      // The force per component in LSB: w excess / len with the root's
      // floor (rest / (len - 1): the length and the excess both one short),
      // the Q2.30 ratio (0.5 |w| 2^-30 < 0.5) and the rounding to Len (0.5).
      const double e_force = k * (1 + rest / std::max(len - 1, 1.0)) + dk * (std::abs(excess) + 1);
      for (uint32_t end : {e.a, e.b}) {
        weight[end] += k;
        error[end] += e_force;
        weight_error[end] += dk;
      }
    }
    for (const es::RubberBand& b : m.bands) {
      const uint32_t j =
          sinew::muscle::muscle_vertex_index(arm.muscles().ring_vertices, b.muscle, b.slice, b.ring_vertex);
      for (size_t c = 0; c < 3; ++c)
        force[b.vertex][c] += b.k / 65536.0 * (arm.muscles().vertex[c][j] - before[b.vertex][c]);
      weight[b.vertex] += b.k / 65536.0;
    }
    for (uint32_t v = 0; v < n; ++v) {
      const double ka = m.anchor_stiffness[v] / 65536.0, den = weight[v] + ka;
      for (size_t c = 0; c < 3; ++c) {
        const double r = (force[v][c] + ka * (arm.skin().anchor[c][v] - before[v][c])) / den;
        const double got = arm.skin().position[c][v] - before[v][c];
        // Division rounded (0.5 LSB), the forces' errors over the
        // denominator, and the denominator's own error times the move.
        const double bound = 0.5 + (error[v] + weight_error[v] * std::abs(r)) / den;
        worst_ratio = std::max(worst_ratio, std::abs(got - r) / bound);
        worst_lsb = std::max(worst_lsb, std::abs(got - r));
        before[v][c] = arm.skin().position[c][v];
      }
    }
  }
  std::printf("30 relaxation rounds against §5.2 in double: worst %.2f LSB, %.3f of its rounding bound\n", worst_lsb,
              worst_ratio);
  EXPECT_LE(worst_ratio, 1.0);
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
  // §4.4: the belly's inner slices (their radii and bulge offsets) scale by
  // s = sqrt(rest / present) about the muscle's path, which the humerus
  // carries unchanged when only the elbow moves (origin and pivot both on
  // it). §5.1: an anchor over the belly is trilinear in its cell's corners,
  // so it rises by (s - 1) times its height above the path, at least the
  // belly's half-thickness h (the skin lies outside the muscle); the skin
  // there follows its anchors (its neighbours rise alike). h: the thinnest
  // slice under the band (x in [0.12, 0.20] m: slices 2-5).
  const double s = arm.muscles().scale[0] / 1073741824.0;
  double h = 1;
  for (uint32_t k = 2; k <= 5; ++k) h = std::min(h, arm.metres(arm.muscle_model().muscles[0].half_thickness[k]));
  std::printf("bulge at 150 deg: +%.2f mm over rest (skinning alone: %+.2f mm; bound (s - 1) h = %.2f mm, s %.4f)\n",
              (last - first) * 1e3, (skinned_last - first) * 1e3, (s - 1) * h * 1e3, s);
  EXPECT_GT(s, 1.0) << "flexion shortens the biceps";
  EXPECT_GE(last - first, (s - 1) * h) << "the skin rises with the belly's swelling";
}
