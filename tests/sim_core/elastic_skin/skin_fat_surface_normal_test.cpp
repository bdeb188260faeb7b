// The fat layer along the skin's current normal (LEMAN §5.6), global and per
// point, with solver.fat_normal = kSurface: a flat 5 x 5 sheet of skin
// (triangulated) whose anchors lie 1 cm inside a sphere of radius 10 (its
// top nearly flat under the sheet), every anchor normal tilted 40 degrees
// off the sheet's normal. After the step each fat point lies on the sphere,
// so the skin sits its fat thickness above the sphere along the normal the
// fat was laid on:
//   surface (mesh) normal, ~ the sphere's radial:  height = fat
//   anchor normal, 40 degrees off the radial:      height = fat cos 40
//   no fat:                                         height = 0
// Bound: the push-out lands within a few LSB outside the surface, the
// mesh normal of a sheet lying on a radius-10 sphere is within edge / R =
// 1e-3 rad of the radial direction (cos within 5e-7), and the Len and
// Q2.30 roundings are ~1e-6 of a rig unit: 1e-5 of height covers all and
// is 1/20 of the smallest fat used below.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "dynamic_skin_fixture.hpp"
#include "sim_core/elastic_skin/surface_normals.hpp"
#include "tests/sim_core/muscle/anatomy_fixture.hpp"

using sinew::test::ArmAnatomy;
using sinew::test::DynamicSkin;
using sinew::test::to_len;
namespace es = sinew::elastic_skin;

namespace {

constexpr double kFatSheetSphereRadius = 10.0;
constexpr double kFatSheetTilt = 40.0 * 3.14159265358979323846 / 180.0;
constexpr int kFatSheetSide = 5;
constexpr double kFatSheetSpacing = 0.01;
constexpr double kFatSheetHeightBound = 1e-5;

struct FatSheetRun {
  std::vector<double> height;  // radial distance above the sphere per vertex
  uint32_t inside_after = 0;
};

// `own_fat` at the centre vertex only, `global_fat` for all.
FatSheetRun run_fat_sheet(es::SkinMode mode, es::FatNormal normal, double global_fat, double own_fat) {
  DynamicSkin s;
  s.model.solver.mode = static_cast<uint8_t>(mode);
  s.model.solver.fat_normal = static_cast<uint8_t>(normal);
  s.model.solver.fat_thickness = sinew::test::to_len(global_fat);
  s.model.params.iterations = 1;  // static: one relaxation, then every penetration removed
  const uint32_t centre = (kFatSheetSide / 2) * kFatSheetSide + kFatSheetSide / 2;
  for (int i = 0; i < kFatSheetSide; ++i)
    for (int k = 0; k < kFatSheetSide; ++k) {
      const uint32_t v = static_cast<uint32_t>(i * kFatSheetSide + k);
      s.add_vertex_with_normal((i - kFatSheetSide / 2) * kFatSheetSpacing, -0.01,
                               (k - kFatSheetSide / 2) * kFatSheetSpacing, std::sin(kFatSheetTilt),
                               std::cos(kFatSheetTilt), 0, 2.0, v == centre ? own_fat : 0.0);
    }
  for (int i = 0; i + 1 < kFatSheetSide; ++i)
    for (int k = 0; k + 1 < kFatSheetSide; ++k) {
      const uint32_t a = static_cast<uint32_t>(i * kFatSheetSide + k), b = a + 1, c = a + kFatSheetSide, d = c + 1;
      s.add_triangle(a, b, d);
      s.add_triangle(a, d, c);
    }
  s.add_sphere(0, -kFatSheetSphereRadius, 0, kFatSheetSphereRadius);
  EXPECT_TRUE(s.finish());
  FatSheetRun out;
  // Dynamic: the skin settles on the sphere over 0.5 s at 1 kHz.
  const int ticks = mode == es::SkinMode::kDynamic ? 500 : 1;
  for (int t = 0; t < ticks; ++t) EXPECT_TRUE(s.step(1000).ok());
  out.inside_after = s.state.stats.inside_after;
  for (uint32_t v = 0; v < s.model.vertex_count; ++v)
    out.height.push_back(std::hypot(s.pos(0, v), s.pos(1, v) + kFatSheetSphereRadius, s.pos(2, v)) -
                         kFatSheetSphereRadius);
  return out;
}

// The anchor-normal contrast lays the fat up to 0.05 sin 40 = 0.032 sideways
// from vertices up to 0.02 off the pole: the sphere's normal there turns by
// up to (0.02 + 0.032) / R = 5.2e-3 rad, moving the height by up to
// 0.032 x 5.2e-3 = 1.7e-4. Still 20x below the surface case's lead,
// 0.02 (1 - cos 40) = 4.7e-3.
constexpr double kFatSheetAnchorBound = 2e-4;

void expect_heights(const FatSheetRun& r, double centre_height, double other_height, const char* what,
                    double bound = kFatSheetHeightBound) {
  const uint32_t centre = (kFatSheetSide / 2) * kFatSheetSide + kFatSheetSide / 2;
  EXPECT_EQ(r.inside_after, 0u) << what;
  for (uint32_t v = 0; v < r.height.size(); ++v)
    EXPECT_NEAR(r.height[v], v == centre ? centre_height : other_height, bound) << what << ", vertex " << v;
}

}  // namespace

TEST(SkinFatSurfaceNormal, StaticSkinSitsItsFatAboveThePrimitiveAlongTheMeshNormal) {
  const double global = 0.02, own = 0.03;
  expect_heights(run_fat_sheet(es::SkinMode::kStatic, es::FatNormal::kSurface, global, own), global + own, global,
                 "static, surface normal");
  // The anchor normal (the default) lays the fat 40 degrees off: thinner.
  expect_heights(run_fat_sheet(es::SkinMode::kStatic, es::FatNormal::kAnchor, global, own),
                 (global + own) * std::cos(kFatSheetTilt), global * std::cos(kFatSheetTilt), "static, anchor normal",
                 kFatSheetAnchorBound);
  // Fat switched off: the skin lies on the sphere.
  expect_heights(run_fat_sheet(es::SkinMode::kStatic, es::FatNormal::kSurface, 0, 0), 0, 0, "static, no fat");
}

TEST(SkinFatSurfaceNormal, DynamicSkinSitsItsFatAboveThePrimitiveAlongTheMeshNormal) {
  // Global fat only: a per-point bump 3 times the edge length would tilt its
  // neighbours' mesh normals (as it should) and the heights with them.
  const double global = 0.02;
  expect_heights(run_fat_sheet(es::SkinMode::kDynamic, es::FatNormal::kSurface, global, 0), global, global,
                 "dynamic, surface normal");
  expect_heights(run_fat_sheet(es::SkinMode::kDynamic, es::FatNormal::kAnchor, global, 0),
                 global * std::cos(kFatSheetTilt), global * std::cos(kFatSheetTilt), "dynamic, anchor normal",
                 kFatSheetAnchorBound);
  expect_heights(run_fat_sheet(es::SkinMode::kDynamic, es::FatNormal::kSurface, 0, 0), 0, 0, "dynamic, no fat");
}

TEST(SkinFatSurfaceNormal, PerPointFatShowsUpAtThatVertexOnly) {
  // Per-point thickness alone: the centre sits 0.03 up, every other vertex
  // on the sphere (a per-point value leaking to its neighbours fails).
  expect_heights(run_fat_sheet(es::SkinMode::kStatic, es::FatNormal::kSurface, 0, 0.03), 0.03, 0, "static, per point");
}

TEST(SkinFatSurfaceNormal, RefusesAnUnknownSwitchAndFacesOutOfRange) {
  DynamicSkin s;
  s.add_vertex(0, 0, 0, 1.0);
  s.add_vertex(0.01, 0, 0, 1.0);
  s.add_vertex(0, 0, 0.01, 1.0);
  s.add_triangle(0, 1, 3);
  s.model.solver.fat_normal = static_cast<uint8_t>(es::FatNormal::kSurface);
  ASSERT_TRUE(s.finish());
  EXPECT_FALSE(s.step(1000).ok());  // vertex 3 does not exist
  s.triangles.back() = 2;
  s.model.triangles = s.triangles;
  EXPECT_TRUE(s.step(1000).ok());
  s.model.solver.fat_normal = 2;
  EXPECT_FALSE(s.step(1000).ok());
}

namespace {

// Area-weighted vertex normals of the skin (double oracle of
// estimate_surface_normals), turned to the anchor normal's side, and per
// vertex the bound on the fixed-point estimate's angle from them: edge
// components rounded by up to 4 LSB (|de| <= 4 sqrt 3) move each face's
// cross by up to |de1| |e2| + |e1| |de2| + |de1| |de2|; summed over the
// vertex's faces and divided by the sum's length, plus 2^-28 for the
// narrowing to 30 bits and the normalisation.
void fat_arm_oracle_normals(const es::SkinModel& m, const es::SkinState& s, std::vector<std::array<double, 3>>* out,
                            std::vector<double>* bound) {
  out->assign(m.vertex_count, {0, 0, 0});
  std::vector<double> slack(m.vertex_count, 0);
  const double de = 4 * std::sqrt(3.0);
  for (size_t f = 0; f + 2 < m.triangles.size(); f += 3) {
    const uint32_t id[3] = {m.triangles[f], m.triangles[f + 1], m.triangles[f + 2]};
    double p[3][3];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) p[k][c] = s.position[c][id[k]];
    const double e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
    const double e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double err = de * (std::hypot(e1[0], e1[1], e1[2]) + std::hypot(e2[0], e2[1], e2[2])) + de * de;
    for (uint32_t v : id) {
      for (int c = 0; c < 3; ++c) (*out)[v][c] += n[c];
      slack[v] += err;
    }
  }
  bound->assign(m.vertex_count, -1);
  for (uint32_t v = 0; v < m.vertex_count; ++v) {
    auto& n = (*out)[v];
    const double len = std::hypot(n[0], n[1], n[2]);
    if (len == 0) continue;
    const double side = n[0] * s.normal[0][v] + n[1] * s.normal[1][v] + n[2] * s.normal[2][v];
    for (double& c : n) c = (side < 0 ? -c : c) / len;
    (*bound)[v] = slack[v] / len + std::ldexp(1.0, -28);
  }
}

}  // namespace

TEST(SkinFatSurfaceNormal, BentArmSkinLiesItsFatOutsideAlongTheCurrentMeshNormal) {
  // The built-in arm at 100 degrees of elbow, 30 of shoulder, static skin.
  ArmAnatomy arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  arm.set("elbow.0", 100);
  arm.set("shoulder.0", 30);
  ASSERT_TRUE(arm.step_muscles().ok());
  const double fat_m = 0.004;
  const auto run = [&](double fat_metres, std::vector<std::array<double, 3>>* pos, std::vector<uint64_t>* memory,
                       es::SkinState* state) {
    es::SkinModel m = arm.skin_model();
    m.solver.fat_normal = static_cast<uint8_t>(es::FatNormal::kSurface);
    m.triangles = arm.rig().triangles;
    // One round: the relaxation runs the same with and without fat, only
    // the final reaction pass (all penetration removed) sees the fat.
    m.params.iterations = 1;
    m.solver.fat_thickness =
        static_cast<sinew::fx::Len>(std::llround(std::ldexp(fat_metres, 20 - arm.length_exponent())));
    memory->assign(es::skin_state_bytes(m) / 8 + 1, 0);
    EXPECT_TRUE(es::skin_init(m, memory->data(), memory->size() * 8, state).ok());
    EXPECT_TRUE(es::skin_step(m, arm.muscle_model(), arm.muscles(), arm.engine().model, state).ok());
    EXPECT_EQ(state->stats.inside_after, 0u);
    pos->resize(m.vertex_count);
    for (uint32_t v = 0; v < m.vertex_count; ++v)
      for (int c = 0; c < 3; ++c) (*pos)[v][c] = arm.metres(state->position[c][v]);
    return m;
  };
  std::vector<std::array<double, 3>> with_fat, without_fat;
  std::vector<uint64_t> mem_a, mem_b;
  es::SkinState sa, sb;
  const es::SkinModel m = run(fat_m, &with_fat, &mem_a, &sa);
  run(0, &without_fat, &mem_b, &sb);
  // The estimate from the final skin against the double oracle.
  es::estimate_surface_normals(m, &sa);
  std::vector<std::array<double, 3>> oracle;
  std::vector<double> bound;
  fat_arm_oracle_normals(m, sa, &oracle, &bound);
  double worst_angle = 0, worst_bound = 0;
  uint32_t checked = 0;
  for (uint32_t v = 0; v < m.vertex_count; ++v) {
    if (bound[v] < 0) continue;
    // The angle from the cross and dot products (acos of the dot would read
    // the Q2.30 vector's length error, a few LSB, as an angle).
    const double u[3] = {sa.surface_normal[0][v] / 1073741824.0, sa.surface_normal[1][v] / 1073741824.0,
                         sa.surface_normal[2][v] / 1073741824.0};
    const double* o = oracle[v].data();
    const double cx = u[1] * o[2] - u[2] * o[1], cy = u[2] * o[0] - u[0] * o[2], cz = u[0] * o[1] - u[1] * o[0];
    const double angle = std::atan2(std::hypot(cx, cy, cz), u[0] * o[0] + u[1] * o[1] + u[2] * o[2]);
    EXPECT_LE(angle, bound[v]) << "vertex " << v;
    worst_angle = std::max(worst_angle, angle);
    worst_bound = std::max(worst_bound, bound[v]);
    ++checked;
  }
  EXPECT_EQ(checked, m.vertex_count);
  // The fat moves the skin out along the mesh normal by at most the fat
  // thickness: a vertex over a primitive moves along the primitive's
  // gradient g until its fat point p - fat n is outside; on a flat face that
  // is fat cos(g, n) along g, fat cos^2 along n, and a convex primitive (the
  // arm's) curves away, so less; a vertex over no primitive settles at a
  // weighted mean of its neighbours and its anchor (which does not move),
  // so it moves no further than they do. Plus the two runs' roundings
  // (sqrt 3 / 2 LSB each). And visibly: fat switched off moves nothing, so
  // the lower bound of a quarter of the thickness fails.
  double largest_out = 0;
  for (uint32_t v = 0; v < m.vertex_count; ++v) {
    double along = 0;
    for (int c = 0; c < 3; ++c) along += (with_fat[v][c] - without_fat[v][c]) * oracle[v][c];
    largest_out = std::max(largest_out, along);
  }
  std::printf(
      "bent arm, fat %.1f mm along the mesh normal: largest outward offset %.3f mm, normal error %.2e rad (bound "
      "%.2e)\n",
      fat_m * 1e3, largest_out * 1e3, worst_angle, worst_bound);
  EXPECT_GT(largest_out, 0.25 * fat_m);
  EXPECT_LE(largest_out, fat_m + std::sqrt(3.0) * arm.metres(1));
}
