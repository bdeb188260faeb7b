// The fat layer (LEMAN §5.6) in the static relaxation: the skin settles
// its fat thickness (per point plus global) outside a primitive, along the
// outward normal; without fat it would touch the primitive.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "dynamic_skin_fixture.hpp"

using sinew::test::DynamicSkin;
using sinew::test::to_len;

TEST(SkinFatStatic, SkinKeepsItsFatThicknessOutsideThePrimitive) {
  // Two points whose anchors lie inside a sphere of radius 0.2 (at radius
  // 0.1): one with its own fat 0.03, one with none; then a global 0.02.
  const auto radii = [](double global_fat) {
    DynamicSkin s;
    s.model.solver.mode = static_cast<uint8_t>(sinew::elastic_skin::SkinMode::kStatic);
    s.add_vertex(0.1, 0, 0, 2.0, 0.03);
    s.add_vertex(0, 0.1, 0, 2.0, 0.0);
    s.add_sphere(0, 0, 0, 0.2);
    s.model.solver.fat_thickness = to_len(global_fat);
    EXPECT_TRUE(s.finish());
    EXPECT_TRUE(s.step(1000).ok());
    EXPECT_EQ(s.state.stats.inside_after, 0u);
    return std::array<double, 2>{std::hypot(s.pos(0, 0), s.pos(1, 0)), std::hypot(s.pos(0, 1), s.pos(1, 1))};
  };
  // The last iteration removes all penetration of the fat point (skin -
  // fat along the normal): the skin at 0.2 + fat, within the push-out's
  // rounding (1e-5). Fat switched off would leave both at 0.2.
  const auto own = radii(0.0);
  EXPECT_NEAR(own[0], 0.23, 1e-4);
  EXPECT_NEAR(own[1], 0.20, 1e-4);
  const auto both = radii(0.02);
  EXPECT_NEAR(both[0], 0.25, 1e-4);
  EXPECT_NEAR(both[1], 0.22, 1e-4);
}
