// Deformed-cylinder muscles on the built-in arm: volume across flexion,
// biceps width growing with flexion, recomputation only when needed.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "anatomy_fixture.hpp"

using sinew::test::ArmAnatomy;
namespace muscle = sinew::muscle;

namespace {

using P = std::array<double, 3>;

double signed_tet(const P& a, const P& b, const P& c) {
  return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
          a[2] * (b[0] * c[1] - b[1] * c[0])) /
         6;
}

// Volume enclosed by the slice rings, closed by fans at the end slices.
double muscle_volume(ArmAnatomy& arm, uint32_t m) {
  const uint32_t ring = arm.muscles().ring_vertices;
  const auto vert = [&](uint32_t k, uint32_t j) {
    return P{arm.muscle_vertex(0, m, k, j), arm.muscle_vertex(1, m, k, j), arm.muscle_vertex(2, m, k, j)};
  };
  const auto centre = [&](uint32_t k) {
    const muscle::SliceFrame& f = arm.muscles().frames[m * muscle::kSlices + k];
    return P{arm.metres(f.centre.x), arm.metres(f.centre.y), arm.metres(f.centre.z)};
  };
  double v = 0;
  for (uint32_t k = 0; k + 1 < muscle::kSlices; ++k)
    for (uint32_t j = 0; j < ring; ++j) {
      const uint32_t jn = (j + 1) % ring;
      v += signed_tet(vert(k, j), vert(k, jn), vert(k + 1, jn));
      v += signed_tet(vert(k, j), vert(k + 1, jn), vert(k + 1, j));
    }
  for (uint32_t j = 0; j < ring; ++j) {
    const uint32_t jn = (j + 1) % ring;
    v += signed_tet(centre(0), vert(0, jn), vert(0, j));
    v += signed_tet(centre(7), vert(7, j), vert(7, jn));
  }
  return std::fabs(v);
}

double widest_inner_slice(ArmAnatomy& arm, uint32_t m, bool thickness) {
  double w = 0;
  for (uint32_t k = 1; k + 1 < muscle::kSlices; ++k) {
    const muscle::SliceFrame& f = arm.muscles().frames[m * muscle::kSlices + k];
    w = std::max(w, arm.metres(thickness ? f.radius_y : f.radius_x));
  }
  return w;
}

// Volume of each muscle over 0..150 deg of elbow flexion, relative to rest.
void volume_band(ArmAnatomy& arm, const char* label, double lo[2], double hi[2]) {
  ASSERT_TRUE(arm.ok()) << arm.error();
  ASSERT_TRUE(arm.step_muscles().ok());
  const double rest[2] = {muscle_volume(arm, 0), muscle_volume(arm, 1)};
  std::printf("%s: volume at rest: biceps %.3f cm^3, triceps %.3f cm^3\n", label, rest[0] * 1e6, rest[1] * 1e6);
  lo[0] = lo[1] = hi[0] = hi[1] = 1;
  for (int a = 0; a <= 150; a += 10) {
    arm.set("elbow.0", a);
    ASSERT_TRUE(arm.step_muscles().ok());
    const double r0 = muscle_volume(arm, 0) / rest[0], r1 = muscle_volume(arm, 1) / rest[1];
    if (a % 50 == 0)
      std::printf("  elbow %3d deg: biceps volume %.4f of rest (scale %.4f), triceps %.4f (scale %.4f)\n", a, r0,
                  std::ldexp(arm.muscles().scale[0], -30), r1, std::ldexp(arm.muscles().scale[1], -30));
    lo[0] = std::min(lo[0], r0), hi[0] = std::max(hi[0], r0);
    lo[1] = std::min(lo[1], r1), hi[1] = std::max(hi[1], r1);
  }
  std::printf("%s: volume band over 0..150 deg: biceps [%.4f, %.4f], triceps [%.4f, %.4f]\n", label, lo[0], hi[0],
              lo[1], hi[1]);
}

}  // namespace

// The paper's default deformed cylinder (no pivot): every section shortens
// with the path, so sqrt(rest / present) keeps the volume up to the end
// sections (§4.4). Stated band: within 3 %.
TEST(Muscle, DefaultMuscleVolumeStaysWithinThreePercentAcrossFullFlexion) {
  ArmAnatomy arm([](sinew::anatomy_build::AnatomySpec& s) {
    for (auto& m : s.muscles) m.has_pivot = false;
  });
  double lo[2], hi[2];
  volume_band(arm, "default (no pivot)", lo, hi);
  for (int m = 0; m < 2; ++m) {
    EXPECT_GT(lo[m], 0.97);
    EXPECT_LT(hi[m], 1.03);
  }
}

// With a pivot the sections before it keep their length, so the volume
// grows with the scale of the inner slices (the paper keeps the rule
// anyway: "exact volume preservation is not biologically justified").
// Stated band for the arm's pivoted muscles: 0.85..1.30.
TEST(Muscle, PivotedMuscleVolumeStaysWithinItsStatedBand) {
  ArmAnatomy arm;
  double lo[2], hi[2];
  volume_band(arm, "arm (pivots)", lo, hi);
  for (int m = 0; m < 2; ++m) {
    EXPECT_GT(lo[m], 0.85);
    EXPECT_LT(hi[m], 1.30);
  }
}

TEST(Muscle, BicepsWidthGrowsWithElbowFlexion) {
  ArmAnatomy arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  double previous = 0, first = 0, last = 0;
  // Up to 135 deg: past it the folded forearm carries the insertion away
  // from the pivot again (printed below, not checked).
  for (int a = 0; a <= 150; a += 15) {
    arm.set("elbow.0", a);
    ASSERT_TRUE(arm.step_muscles().ok());
    const double w = widest_inner_slice(arm, 0, false), t = widest_inner_slice(arm, 0, true);
    std::printf("biceps at elbow %3d deg: half width %.2f mm, half thickness %.2f mm, length %.1f mm\n", a, w * 1e3,
                t * 1e3, arm.metres(arm.muscles().length[0]) * 1e3);
    if (a <= 135) EXPECT_GE(w, previous) << "width must not shrink as the elbow flexes";
    if (a == 0) first = w;
    if (a <= 135) last = w;
    previous = w;
  }
  std::printf("biceps width ratio 135 deg / 0 deg: %.4f\n", last / first);
  EXPECT_GT(last / first, 1.10);
}

TEST(Muscle, RecomputedOnlyWhenAJointBetweenOriginAndInsertionMoves) {
  ArmAnatomy arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  ASSERT_TRUE(arm.step_muscles().ok());
  EXPECT_EQ(arm.muscles().stats.recomputed, 2u) << "the first step computes every muscle";
  ASSERT_TRUE(arm.step_muscles().ok());
  EXPECT_EQ(arm.muscles().stats.recomputed, 0u) << "same pose again: nothing moved";
  arm.set("wrist.0", 40);
  ASSERT_TRUE(arm.step_muscles().ok());
  std::printf("muscles recomputed after a wrist move: %u; ", arm.muscles().stats.recomputed);
  EXPECT_EQ(arm.muscles().stats.recomputed, 0u);
  arm.set("elbow.0", 40);
  ASSERT_TRUE(arm.step_muscles().ok());
  std::printf("after an elbow move: %u\n", arm.muscles().stats.recomputed);
  EXPECT_EQ(arm.muscles().stats.recomputed, 2u);
}

TEST(Muscle, RestLengthGivesUnitScaleAtRest) {
  ArmAnatomy arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  ASSERT_TRUE(arm.step_muscles().ok());
  EXPECT_EQ(arm.muscles().scale[0], sinew::fx::kUnitOne);
  EXPECT_EQ(arm.muscles().scale[1], sinew::fx::kUnitOne);
}
