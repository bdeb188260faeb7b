// The elastic skin of anatomically-based-modeling §5 against the paper's
// formulas, each evaluated independently in double: the edge stiffness of
// eq. (1), the anchor stiffness of eq. (2), the 90 % rest length and the 0.1
// push-back of compressed edges (§5.2), the collision sphere under each
// anchor (§5.2), and the parametric trilinear map and its Newton-Raphson
// inverse (§5.1, Figure 6). Bounds come from the Q formats of
// skin_model.hpp and the integer length of the builder, not from runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>
#include <vector>

#include "host_tools/layers/anatomy/trilinear_inverse.hpp"
#include "sim_core/elastic_skin/relaxation.hpp"
#include "sim_core/elastic_skin/virtual_anchors.hpp"
#include "tests/sim_core/muscle/anatomy_fixture.hpp"

using sinew::test::ArmAnatomy;

namespace {

namespace es = sinew::elastic_skin;
namespace ab = sinew::anatomy_build;

constexpr double kQ16 = 65536.0;

// Rest positions of the rig in Len units (double, exact).
struct FormulaMesh {
  std::vector<double> p[3];
  std::vector<uint32_t> tri;
  double len(uint32_t a, uint32_t b) const {
    const double d[3] = {p[0][b] - p[0][a], p[1][b] - p[1][a], p[2][b] - p[2][a]};
    return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  }
  double area(size_t t) const {
    const uint32_t a = tri[t], b = tri[t + 1], c = tri[t + 2];
    const double e1[3] = {p[0][b] - p[0][a], p[1][b] - p[1][a], p[2][b] - p[2][a]};
    const double e2[3] = {p[0][c] - p[0][a], p[1][c] - p[1][a], p[2][c] - p[2][a]};
    const double x = e1[1] * e2[2] - e1[2] * e2[1], y = e1[2] * e2[0] - e1[0] * e2[2],
                 z = e1[0] * e2[1] - e1[1] * e2[0];
    return std::sqrt(x * x + y * y + z * z) / 2;
  }
};

FormulaMesh formula_mesh(const sinew::rig::Rig& rig) {
  FormulaMesh m;
  for (int c = 0; c < 3; ++c)
    for (int32_t v : rig.position[c]) m.p[c].push_back(v);
  m.tri.assign(rig.triangles.begin(), rig.triangles.end());
  return m;
}

}  // namespace

TEST(SkinFormulaPaper, EdgeStiffnessIsEquation1) {
  // k_e = (a1 + a2) / len^2 with the areas of the triangles sharing the
  // edge, at rest. The builder measures len with the integer length (off
  // by at most 1 LSB of Len: relative error 1 / len, squared: ~2 / len) and
  // stores Q16.16 rounded (0.5 LSB). Areas over a squared length are
  // dimensionless: no unit enters.
  ArmAnatomy arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  const FormulaMesh mesh = formula_mesh(arm.rig());
  std::map<std::pair<uint32_t, uint32_t>, double> areas;
  for (size_t t = 0; t + 2 < mesh.tri.size(); t += 3)
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = mesh.tri[t + static_cast<size_t>(i)], b = mesh.tri[t + static_cast<size_t>((i + 1) % 3)];
      areas[{std::min(a, b), std::max(a, b)}] += mesh.area(t);
    }
  ASSERT_EQ(arm.model().edges.size(), areas.size()) << "one spring per mesh edge";
  double worst_ratio = 0;
  for (const es::Edge& e : arm.model().edges) {
    const auto it = areas.find({e.a, e.b});
    ASSERT_NE(it, areas.end()) << "edge " << e.a << "-" << e.b << " is not a mesh edge";
    const double l = mesh.len(e.a, e.b);
    const double k = it->second / (l * l);
    const double bound = 0.5 + k * kQ16 * (2.0 / (l - 1.0) + 1e-12);
    const double err = std::abs(static_cast<double>(e.k) - k * kQ16);
    worst_ratio = std::max(worst_ratio, err / bound);
    ASSERT_LE(err, bound) << "edge " << e.a << "-" << e.b;
  }
  std::printf("eq. (1): %zu edges, worst error %.3f of its bound\n", arm.model().edges.size(), worst_ratio);
}

TEST(SkinFormulaPaper, AnchorStiffnessIsEquation2) {
  // k_a = C_a sum_i a_i / 3 over the triangles at the vertex, areas in units
  // of the mean rest edge length squared (skin_model.hpp). The mean length
  // carries the integer length's error (<= 1 LSB each): relative 2 / l_min
  // on its square.
  ArmAnatomy arm([](ab::AnatomySpec& s) { s.skin.anchor_coefficient = 0.1; });
  ASSERT_TRUE(arm.ok()) << arm.error();
  const FormulaMesh mesh = formula_mesh(arm.rig());
  const uint32_t n = arm.rig().vertex_count();
  std::vector<double> share(n, 0);
  for (size_t t = 0; t + 2 < mesh.tri.size(); t += 3)
    for (int i = 0; i < 3; ++i) share[mesh.tri[t + static_cast<size_t>(i)]] += mesh.area(t) / 3;
  double sum = 0, shortest = 1e300;
  for (const es::Edge& e : arm.model().edges) {
    const double l = mesh.len(e.a, e.b);
    sum += l;
    shortest = std::min(shortest, l);
  }
  const double mean = sum / static_cast<double>(arm.model().edges.size());
  const double c_a = 0.1;  // the paper's C_a for the monkey model
  ASSERT_EQ(arm.model().anchor_stiffness.size(), n);
  for (uint32_t v = 0; v < n; ++v) {
    const double k = c_a * share[v] / (mean * mean);
    const double bound = 0.5 + k * kQ16 * (2.0 / (shortest - 1.0) + 1e-12);
    ASSERT_LE(std::abs(static_cast<double>(arm.model().anchor_stiffness[v]) - k * kQ16), bound) << "vertex " << v;
  }
}

TEST(SkinFormulaPaper, RestLengthIsNinetyPercentOfTheExtractedLength) {
  // §5.2: "the rest length of the edge is taken to be some percentage of the
  // measured default length ... Suppose the user has chosen 90%". Rounded
  // to Len (0.5 LSB) from the integer length (1 LSB, times 0.9).
  ArmAnatomy arm([](ab::AnatomySpec& s) { s.skin.rest_length_ratio = 0.9; });
  ASSERT_TRUE(arm.ok()) << arm.error();
  const FormulaMesh mesh = formula_mesh(arm.rig());
  for (const es::Edge& e : arm.model().edges)
    ASSERT_LE(std::abs(static_cast<double>(e.rest) - 0.9 * mesh.len(e.a, e.b)), 0.5 + 0.9)
        << "edge " << e.a << "-" << e.b;
}

TEST(SkinFormulaPaper, CompressedEdgesPushBackWithATenth) {
  // §5.2 with the paper's 90 % and 0.1: the multiplier of k_e is 1 for a
  // length excess >= 0, 0.1 below -0.1 x rest, and interpolated linearly in
  // between. Error: push_back and the band are Q2.30 (2^-30 each), the band
  // in Len is rounded (0.5 LSB, a relative 0.5 / band on the slope), the
  // multiplier rounds to Q2.30 and the result to Q16.16 (0.5 LSB).
  es::SkinParams p;  // defaults: push_back 0.1, compression band 0.1
  const es::Stiffness k = 3 * es::kStiffnessOne / 2;
  for (const int32_t rest : {1000, 40000, 1 << 20, 123457}) {
    const double band = 0.1 * rest;
    for (int step = -300; step <= 100; ++step) {
      const int64_t excess = static_cast<int64_t>(std::llround(band * step / 200.0));
      const double x = static_cast<double>(excess);
      const double multiplier = x >= 0 ? 1.0 : (x <= -band ? 0.1 : 1.0 - 0.9 * (-x) / band);
      const double slope_error = x < 0 && -x < band + 1 ? 0.9 * (-x) * (0.5 + 1.0) / (band * (band - 1.5)) : 0.0;
      const double bound = 0.5 + k * (slope_error + 3.0 / 1073741824.0);
      const double got = static_cast<double>(es::effective_stiffness(p, k, excess, rest));
      ASSERT_LE(std::abs(got - k * multiplier), bound) << "rest " << rest << " excess " << excess;
    }
  }
}

TEST(SkinFormulaPaper, VerticesLeaveTheCollisionSphereUnderTheirAnchor) {
  // §5.2: a sphere of radius R whose surface is tangent to the skin at the
  // virtual anchor (centre R below it along the normal); a vertex inside is
  // moved outward to the sphere's surface (along the ray from the centre),
  // one outside stays. Oracle in double; the runtime's unit direction is
  // Q2.30 (a few 2^-30, times R) and every coordinate rounds to Len.
  ArmAnatomy arm([](ab::AnatomySpec& s) { s.skin.collision_radius = 0.02; });
  ASSERT_TRUE(arm.ok()) << arm.error();
  arm.set("elbow.0", 60);
  ASSERT_TRUE(arm.step().ok());
  es::SkinState& s = arm.skin();
  const uint32_t n = arm.skin_model().vertex_count;
  const double radius = arm.skin_model().params.collision_radius;
  ASSERT_GT(radius, 0);
  // Sink every third vertex halfway to its sphere's centre, the rest stay.
  std::vector<double> before[3];
  for (uint32_t v = 0; v < n; ++v) {
    const double normal[3] = {s.normal[0][v] / 1073741824.0, s.normal[1][v] / 1073741824.0,
                              s.normal[2][v] / 1073741824.0};
    for (int c = 0; c < 3; ++c) {
      if (v % 3 == 0) s.position[c][v] = static_cast<int32_t>(std::llround(s.anchor[c][v] - 0.5 * radius * normal[c]));
      before[c].push_back(s.position[c][v]);
    }
  }
  es::collide_with_anchor_spheres(arm.skin_model(), &s);
  uint32_t pushed = 0;
  for (uint32_t v = 0; v < n; ++v) {
    double centre[3], d[3], dist2 = 0;
    for (int c = 0; c < 3; ++c) {
      centre[c] = s.anchor[c][v] - radius * (s.normal[c][v] / 1073741824.0);
      d[c] = before[c][v] - centre[c];
      dist2 += d[c] * d[c];
    }
    const double dist = std::sqrt(dist2);
    if (s.normal[0][v] == 0 && s.normal[1][v] == 0 && s.normal[2][v] == 0) continue;  // no sphere without a normal
    if (dist >= radius - 1) {  // outside (the runtime's 2 LSB of slack aside): untouched
      if (dist > radius + 2)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(s.position[c][v], before[c][v]) << "vertex " << v << " moved";
      continue;
    }
    ++pushed;
    for (int c = 0; c < 3; ++c) {
      const double want = centre[c] + radius * d[c] / dist;
      // centre: the normal's Q2.30 rounding x R plus 1 LSB; direction: 4 x
      // 2^-30 x R; plus the final rounding.
      const double bound = 1.0 + 2.0 + radius * 8.0 / 1073741824.0 + 2.0;
      ASSERT_LE(std::abs(s.position[c][v] - want), bound) << "vertex " << v << " axis " << c;
    }
  }
  std::printf("collision spheres: %u of %u vertices pushed out to their sphere\n", pushed, n);
  EXPECT_GE(pushed, n / 3 - 1);
}

TEST(SkinFormulaPaper, TrilinearInverseRecoversTheParameters) {
  // §5.1: the tri-affine map of a warped cell (Figure 6), inverted by 3D
  // Newton-Raphson. The oracle's forward map is written from the paper's
  // definition: bilinear on each slice quad (c00, c10, c11, c01), linear in
  // u between the slices. Newton converges quadratically on these mildly
  // warped cells: the parameters come back to 1e-9 (far above double's
  // rounding, far below a Q8.24 LSB, 6e-8).
  uint64_t seed = 0x2545F4914F6CDD1Dull;
  const auto jitter = [&seed]() {
    seed ^= seed << 13;
    seed ^= seed >> 7;
    seed ^= seed << 17;
    return (static_cast<double>(seed >> 11) / 9007199254740992.0 - 0.5) * 0.3;
  };
  const double base[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int cell = 0; cell < 50; ++cell) {
    ab::P3 corners[8];
    for (int k = 0; k < 8; ++k)
      for (int c = 0; c < 3; ++c) corners[k][static_cast<size_t>(c)] = 0.02 * (base[k][c] + jitter());
    for (int sample = 0; sample < 20; ++sample) {
      const ab::P3 stu{0.5 + 1.2 * jitter() / 0.3, 0.5 + 1.2 * jitter() / 0.3, 0.5 + 1.2 * jitter() / 0.3};
      ab::P3 target{};
      for (size_t c = 0; c < 3; ++c) {
        double slice[2];
        for (int side = 0; side < 2; ++side) {
          const ab::P3* q = corners + side * 4;
          const double s = stu[0], t = stu[1];
          slice[side] = (1 - s) * (1 - t) * q[0][c] + s * (1 - t) * q[1][c] + s * t * q[2][c] + (1 - s) * t * q[3][c];
        }
        target[c] = (1 - stu[2]) * slice[0] + stu[2] * slice[1];
      }
      ab::P3 got{};
      double residual = 0;
      ASSERT_TRUE(ab::trilinear_inverse(corners, target, &got, &residual));
      for (size_t c = 0; c < 3; ++c) ASSERT_NEAR(got[c], stu[c], 1e-9) << "cell " << cell << " sample " << sample;
    }
  }
}

TEST(SkinFormulaPaper, FixedPointTrilinearMapMatchesTheDefinition) {
  // The runtime's forward map (virtual_anchors.hpp) against the same
  // definition in double: parameters Q8.24 exact, corners Len exact; four
  // products each rounded once (0.5 LSB) and the u blend once more.
  uint64_t seed = 88172645463325252ull;
  const auto next = [&seed]() {
    seed ^= seed << 13;
    seed ^= seed >> 7;
    seed ^= seed << 17;
    return seed;
  };
  for (int k = 0; k < 2000; ++k) {
    sinew::fx::Vec3 corners[8];
    for (auto& q : corners)
      q = {static_cast<int32_t>(next() % (1u << 24)) - (1 << 23), static_cast<int32_t>(next() % (1u << 24)) - (1 << 23),
           static_cast<int32_t>(next() % (1u << 24)) - (1 << 23)};
    const sinew::fx::Lin param[3] = {static_cast<int32_t>(next() % (3u << 24)) - (1 << 24),
                                     static_cast<int32_t>(next() % (3u << 24)) - (1 << 24),
                                     static_cast<int32_t>(next() % (3u << 24)) - (1 << 24)};
    const sinew::fx::Vec3 got = es::trilinear(corners, param);
    const double s = param[0] / 16777216.0, t = param[1] / 16777216.0, u = param[2] / 16777216.0;
    const int32_t out[3] = {got.x, got.y, got.z};
    for (int c = 0; c < 3; ++c) {
      const auto axis = [c](sinew::fx::Vec3 v) { return static_cast<double>(c == 0 ? v.x : (c == 1 ? v.y : v.z)); };
      double slice[2];
      for (int side = 0; side < 2; ++side) {
        const sinew::fx::Vec3* q = corners + side * 4;
        slice[side] =
            (1 - s) * (1 - t) * axis(q[0]) + s * (1 - t) * axis(q[1]) + s * t * axis(q[2]) + (1 - s) * t * axis(q[3]);
      }
      const double want = (1 - u) * slice[0] + u * slice[1];
      // Each slice: three products rounded (0.5 LSB each), and s t rounded
      // to Q8.24 first (0.5 x 2^-24) times its twist |c11 - c10 - c01 + c00|;
      // the u blend weighs the slices' errors by |1 - u| and |u| and rounds.
      double slice_error = 0;
      for (int side = 0; side < 2; ++side) {
        const sinew::fx::Vec3* q = corners + side * 4;
        const double twist = std::abs(axis(q[2]) - axis(q[1]) - axis(q[3]) + axis(q[0]));
        slice_error = std::max(slice_error, 1.5 + twist * 0.5 / 16777216.0);
      }
      const double bound = (std::abs(1 - u) + std::abs(u)) * slice_error + 0.5 + 1e-6;
      ASSERT_LE(std::abs(out[c] - want), bound) << "sample " << k << " axis " << c;
    }
  }
}
