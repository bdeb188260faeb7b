// Rubber bands bind a skin point to the muscle layer where a ray from it,
// perpendicular to the skin, meets the muscle (LEMAN §5.5), whatever muscle
// point the spec named to select the skin point.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "sim_core/muscle/muscle_model.hpp"
#include "tests/sim_core/muscle/anatomy_fixture.hpp"

namespace {

using V3 = std::array<double, 3>;

V3 sub3(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot3(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 cross3(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double len3(const V3& a) { return std::sqrt(dot3(a, a)); }

V3 rest_position(const sinew::test::ArmAnatomy& a, uint32_t v) {
  return {a.metres(a.rig().position[0][v]), a.metres(a.rig().position[1][v]), a.metres(a.rig().position[2][v])};
}
V3 rest_normal(const sinew::test::ArmAnatomy& a, uint32_t v) {
  const V3 n{a.rig().normal[0][v] / 1073741824.0, a.rig().normal[1][v] / 1073741824.0,
             a.rig().normal[2][v] / 1073741824.0};
  const double l = len3(n);
  return {n[0] / l, n[1] / l, n[2] / l};
}
V3 muscle_at(const sinew::test::ArmAnatomy& a, uint32_t m, uint32_t k, uint32_t j) {
  return {a.muscle_vertex(0, m, k, j), a.muscle_vertex(1, m, k, j), a.muscle_vertex(2, m, k, j)};
}

// The oracle, from §5.5's words: the first point where the ray from the
// skin point along its inward normal crosses the muscle's surface (its
// rest mesh, slice to slice), by the plane of each triangle and its
// barycentric coordinates; then the ring vertex nearest that point.
bool traced_ring_vertex(const sinew::test::ArmAnatomy& a, uint32_t ring, uint32_t m, const V3& p, const V3& inward,
                        uint32_t* slice, uint32_t* j_out) {
  double first = std::numeric_limits<double>::infinity();
  for (uint32_t k = 0; k + 1 < sinew::muscle::kSlices; ++k)
    for (uint32_t j = 0; j < ring; ++j) {
      const V3 c[4] = {muscle_at(a, m, k, j), muscle_at(a, m, k, (j + 1) % ring), muscle_at(a, m, k + 1, j),
                       muscle_at(a, m, k + 1, (j + 1) % ring)};
      for (const auto& t : {std::array<V3, 3>{c[0], c[1], c[2]}, std::array<V3, 3>{c[1], c[3], c[2]}}) {
        const V3 normal = cross3(sub3(t[1], t[0]), sub3(t[2], t[0]));
        const double facing = dot3(normal, inward);
        if (std::fabs(facing) < 1e-15) continue;
        const double s = dot3(normal, sub3(t[0], p)) / facing;  // along the ray
        if (!(s >= 0 && s < first)) continue;
        const V3 x{p[0] + s * inward[0], p[1] + s * inward[1], p[2] + s * inward[2]};
        // Inside the triangle: on the inner side of each edge.
        bool inside = true;
        for (int e = 0; e < 3 && inside; ++e)
          inside = dot3(cross3(sub3(t[(e + 1) % 3], t[e]), sub3(x, t[e])), normal) >= 0;
        if (inside) first = s;
      }
    }
  if (!std::isfinite(first)) return false;
  const V3 hit{p[0] + first * inward[0], p[1] + first * inward[1], p[2] + first * inward[2]};
  double best = std::numeric_limits<double>::infinity();
  for (uint32_t k = 0; k < sinew::muscle::kSlices; ++k)
    for (uint32_t j = 0; j < ring; ++j) {
      const double d = len3(sub3(muscle_at(a, m, k, j), hit));
      if (d < best) best = d, *slice = k, *j_out = j;
    }
  return true;
}

}  // namespace

TEST(RubberBandRay, TargetsTheMusclePointUnderTheSkinPoint) {
  // The arm's own bands (the skin vertex nearest each belly's outer point),
  // plus one from the skin vertex whose normal points most nearly away from
  // the first band's, on the back of the upper arm, while the spec names the
  // biceps' front point: the ray from the back decides.
  sinew::test::ArmAnatomy probe;
  ASSERT_TRUE(probe.ok()) << probe.error();
  ASSERT_EQ(probe.muscle_model().ring_vertices, 8u);
  const uint32_t front = probe.skin_model().bands[0].vertex;
  const V3 front_p = rest_position(probe, front), front_n = rest_normal(probe, front);
  int back = -1;
  double most = 2;
  for (uint32_t v = 0; v < probe.rig().vertex_count(); ++v) {
    const V3 p = rest_position(probe, v);
    if (std::fabs(p[0] - front_p[0]) > 0.01) continue;  // the same section of the arm
    const double facing = dot3(rest_normal(probe, v), front_n);
    if (facing < most) most = facing, back = static_cast<int>(v);
  }
  ASSERT_GE(back, 0);
  sinew::test::ArmAnatomy arm([&](sinew::anatomy_build::AnatomySpec& s) {
    s.skin.bands.push_back({back, 0, 4, 6, 0.5, {}});
  });
  ASSERT_TRUE(arm.ok()) << arm.error();
  ASSERT_TRUE(arm.step_muscles().ok());  // the muscles at the rest pose
  const auto& bands = arm.skin_model().bands;
  ASSERT_EQ(bands.size(), 3u);
  for (size_t i = 0; i < bands.size(); ++i) {
    const auto& b = bands[i];
    const V3 p = rest_position(arm, b.vertex), n = rest_normal(arm, b.vertex);
    uint32_t slice = 0, j = 0;
    ASSERT_TRUE(traced_ring_vertex(arm, 8, b.muscle, p, {-n[0], -n[1], -n[2]}, &slice, &j)) << "band " << i;
    std::printf("band %zu: skin vertex %u -> muscle %u slice %u ring vertex %u (the traced ray: slice %u, %u)\n", i,
                b.vertex, b.muscle, b.slice, b.ring_vertex, slice, j);
    EXPECT_EQ(b.slice, slice) << "band " << i;
    EXPECT_EQ(b.ring_vertex, j) << "band " << i;
  }
  // From the back the ray reaches the biceps' back, not the named front point.
  EXPECT_NE(bands[2].ring_vertex, 6u);
}
