// LEMAN §5.2: "Active shapes push the skin to be on the outside, while
// inactive shapes do not affect the skin surface at all." A ring of skin
// anchored inside a sphere, in the static relaxation and in the dynamic
// mode: with the sphere inactive the skin is bit for bit the skin without
// it; with the sphere active every fat point ends outside it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "dynamic_skin_fixture.hpp"

namespace es = sinew::elastic_skin;
using sinew::test::DynamicSkin;

namespace {

enum class Sphere { kNone, kInactive, kActive };

constexpr int kRingVertices = 16;
constexpr double kAnchorRadius = 0.15, kSphereRadius = 0.2, kFat = 0.01;
constexpr int kTicks = 50;

// Positions [tick][axis * n + vertex] in Len LSB after each tick; the bone
// sways along x so the anchors move under the sphere. `fat_radius`: the
// smallest distance of a fat point (the vertex less kFat along its normal)
// from the sphere's centre.
std::vector<std::vector<int32_t>> run_ring(es::SkinMode mode, Sphere sphere, double* fat_radius) {
  DynamicSkin s;
  s.model.solver.mode = static_cast<uint8_t>(mode);
  for (int i = 0; i < kRingVertices; ++i) {
    const double a = 2 * 3.141592653589793 * i / kRingVertices;
    s.add_vertex(kAnchorRadius * std::cos(a), kAnchorRadius * std::sin(a), 0, 2.0, kFat);
  }
  const double rest = 2 * kAnchorRadius * std::sin(3.141592653589793 / kRingVertices);
  for (int i = 0; i < kRingVertices; ++i)
    s.add_edge(static_cast<uint32_t>(i), static_cast<uint32_t>((i + 1) % kRingVertices), 1.0, rest);
  if (sphere != Sphere::kNone) {
    s.add_sphere(0, 0, 0, kSphereRadius);
    s.frames.back().active = sphere == Sphere::kActive ? 1 : 0;
  }
  EXPECT_TRUE(s.finish());
  std::vector<std::vector<int32_t>> out;
  for (int k = 0; k < kTicks; ++k) {
    s.move_bone(0.02 * std::sin(k * 0.2), 0, 0);
    EXPECT_TRUE(s.step(1000).ok());
    std::vector<int32_t> p;
    for (int c = 0; c < 3; ++c) p.insert(p.end(), s.state.position[c].begin(), s.state.position[c].end());
    out.push_back(p);
    for (uint32_t v = 0; v < s.model.vertex_count; ++v) {
      double r2 = 0;
      for (int c = 0; c < 3; ++c) r2 += std::pow(s.pos(c, v) - kFat * s.state.normal[c][v] / 1073741824.0, 2);
      *fat_radius = std::min(*fat_radius, std::sqrt(r2));
    }
  }
  return out;
}

}  // namespace

TEST(PrimitiveActive, InactiveShapesLeaveTheSkinAloneActiveOnesPushItOut) {
  for (const es::SkinMode mode : {es::SkinMode::kStatic, es::SkinMode::kDynamic}) {
    const char* name = mode == es::SkinMode::kStatic ? "static" : "dynamic";
    double fat_none = 1e9, fat_inactive = 1e9, fat_active = 1e9;
    const auto none = run_ring(mode, Sphere::kNone, &fat_none);
    const auto inactive = run_ring(mode, Sphere::kInactive, &fat_inactive);
    const auto active = run_ring(mode, Sphere::kActive, &fat_active);
    ASSERT_EQ(none.size(), static_cast<size_t>(kTicks));
    int differing = 0;
    for (int k = 0; k < kTicks; ++k) {
      EXPECT_EQ(inactive[static_cast<size_t>(k)], none[static_cast<size_t>(k)]) << name << " tick " << k;
      differing += active[static_cast<size_t>(k)] != none[static_cast<size_t>(k)];
    }
    std::printf(
        "%s: inactive sphere identical to none at all %d ticks (fat points down to radius %.4f); active: %d ticks "
        "differ, fat points down to radius %.6f (sphere %.3f)\n",
        name, kTicks, fat_inactive, differing, fat_active, kSphereRadius);
    EXPECT_LT(fat_none, kSphereRadius) << name << ": the anchors put the fat points inside the sphere";
    EXPECT_EQ(differing, kTicks) << name;
    // Outside up to the constraints' tolerance (F >= 1 - 2^-10: the radius
    // within 2^-11 of r) and the Len rounding of each coordinate.
    EXPECT_GE(fat_active, kSphereRadius * (1 - 0x1p-11) - 2.0 / 1048576.0) << name;
  }
}
