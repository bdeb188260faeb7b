// The relaxation's vector kernels (sim_core/elastic_skin/
// relaxation_avx512.cpp, where the CPU runs them) against the scalar
// specification (relaxation.cpp), word for word.
// The edge pass: stretched, compressed
// (within and beyond the push-back band) and zero-length edges, zero
// stiffness, ends at the int32 limits so the difference saturates,
// consecutive and scattered edge lists, lengths that are not a multiple of
// the lane width, and entries the list does not name, which stay untouched.
// The collision pass: vertices outside, inside, on the slack and at their
// sphere's centre, spheres near the int32 limits (the difference and the
// move saturate), radii from 1 LSB up, consecutive and scattered lists.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "sim_core/elastic_skin/relaxation_kernels.hpp"

namespace relaxation_kernel_test {
namespace {

namespace es = sinew::elastic_skin;
namespace ed = sinew::elastic_skin::detail;

constexpr int32_t kUntouched = 0x5A5A5A5A;

struct Outputs {
  std::vector<int32_t> stiffness;
  std::array<std::vector<int32_t>, 3> pull;
};

struct Case {
  es::SkinParams params;
  std::vector<es::Edge> edges;
  std::array<std::vector<int32_t>, 3> position;
  std::vector<uint32_t> moving;
};

int32_t coordinate(std::mt19937_64& rng) {
  switch (rng() % 4) {
    case 0:
      return static_cast<int32_t>(static_cast<uint32_t>(rng()));  // anywhere, the limits included
    case 1:
      // Within 64 of a limit, on its inner side.
      return rng() % 2 == 0 ? INT32_MAX - static_cast<int32_t>(rng() % 64)
                            : INT32_MIN + static_cast<int32_t>(rng() % 64);
    default:
      return static_cast<int32_t>(rng() % 200001) - 100000;  // a skin's scale: edges of tens of thousands
  }
}

Case make_case(std::mt19937_64& rng, uint32_t vertices, uint32_t edge_count, bool consecutive, uint32_t listed) {
  Case c;
  c.params.push_back = static_cast<int32_t>(rng() % (uint64_t{1} << 30));
  c.params.compression_band = 1 + static_cast<int32_t>(rng() % (uint64_t{1} << 30));
  for (auto& column : c.position) {
    column.resize(vertices);
    for (int32_t& x : column) x = coordinate(rng);
  }
  for (uint32_t e = 0; e < edge_count; ++e) {
    es::Edge edge;
    edge.a = static_cast<uint32_t>(rng() % vertices);
    edge.b = rng() % 8 == 0 ? edge.a : static_cast<uint32_t>(rng() % vertices);  // some zero-length
    // The rest near the present length (in and beyond the band on both
    // sides) or anywhere in [0, 2^31).
    int64_t len2 = 0;
    for (const auto& column : c.position) {
      const int64_t d = int64_t{column[edge.b]} - column[edge.a];
      const int64_t w = d > INT32_MAX ? INT32_MAX : (d < INT32_MIN ? INT32_MIN : d);
      len2 += w * w / 4;  // halved lengths: no overflow
    }
    int64_t len = 0;
    while ((len + 1) * (len + 1) <= len2 && len < (int64_t{1} << 31)) len += 1 + (len >> 3);
    len *= 2;
    const int64_t rest = rng() % 2 == 0 ? len + static_cast<int64_t>(rng() % 2001) - 1000 +
                                              (rng() % 2 == 0 ? 0 : len / static_cast<int64_t>(2 + rng() % 20))
                                        : static_cast<int64_t>(rng() % (uint64_t{1} << 31));
    edge.rest = static_cast<int32_t>(rest < 0 ? 0 : (rest > INT32_MAX ? INT32_MAX : rest));
    edge.k = rng() % 6 == 0 ? 0 : static_cast<es::Stiffness>(rng() % (es::kMaxStiffness + 1));
    c.edges.push_back(edge);
  }
  for (uint32_t e = 0; e < edge_count; ++e) c.moving.push_back(e);
  if (!consecutive) std::shuffle(c.moving.begin(), c.moving.end(), rng);
  c.moving.resize(listed);
  return c;
}

Outputs run(ed::RelaxationKernel kernel, const Case& c, uint32_t begin) {
  Outputs out;
  out.stiffness.assign(c.edges.size(), kUntouched);
  for (auto& column : out.pull) column.assign(c.edges.size(), kUntouched);
  const ed::EdgePullJob job{
      &c.params,       c.edges.data(),       {c.position[0].data(), c.position[1].data(), c.position[2].data()},
      c.moving.data(), out.stiffness.data(), {out.pull[0].data(), out.pull[1].data(), out.pull[2].data()}};
  ed::pull_edges_with(kernel, job, begin, static_cast<uint32_t>(c.moving.size()));
  return out;
}

TEST(RelaxationKernel, EdgePassWritesTheSpecificationsWords) {
  if (!ed::relaxation_kernel_supported(ed::RelaxationKernel::kAvx512)) GTEST_SKIP() << "no AVX-512 F/VL/CD on this CPU";
  std::mt19937_64 rng(20261207);
  uint64_t compared = 0;
  for (int round = 0; round < 400; ++round) {
    const uint32_t edge_count = 1 + static_cast<uint32_t>(rng() % 90);
    const bool consecutive = rng() % 2 == 0;
    const uint32_t listed = consecutive ? edge_count : 1 + static_cast<uint32_t>(rng() % edge_count);
    const Case c = make_case(rng, 2 + static_cast<uint32_t>(rng() % 40), edge_count, consecutive, listed);
    const uint32_t begin = static_cast<uint32_t>(rng() % 3 == 0 ? rng() % listed : 0);
    const Outputs spec = run(ed::RelaxationKernel::kScalar, c, begin);
    const Outputs vec = run(ed::RelaxationKernel::kAvx512, c, begin);
    ASSERT_EQ(vec.stiffness, spec.stiffness) << "round " << round;
    for (int a = 0; a < 3; ++a) ASSERT_EQ(vec.pull[a], spec.pull[a]) << "round " << round << " axis " << a;
    compared += listed - begin;
  }
  EXPECT_GT(compared, 8000u);
}

// The cases above reach every kind of lane: otherwise the comparison would
// hold for a kernel that never meets them.
TEST(RelaxationKernel, EdgeCasesCoverEveryKindOfEdge) {
  std::mt19937_64 rng(20261207);
  uint32_t stretched = 0, compressed = 0, idle = 0, saturated = 0;
  for (int round = 0; round < 100; ++round) {
    const Case c = make_case(rng, 40, 64, true, 64);
    const Outputs spec = run(ed::RelaxationKernel::kScalar, c, 0);
    for (uint32_t e = 0; e < 64; ++e) {
      const es::Edge& edge = c.edges[e];
      if (spec.stiffness[e] == 0) {
        ++idle;
        continue;
      }
      bool sat = false;
      // |d| < 2^32, so d^2 / 4 < 2^62 and three of them fit in 64 unsigned bits.
      uint64_t quarter_len2 = 0;
      for (const auto& column : c.position) {
        const int64_t d = int64_t{column[edge.b]} - column[edge.a];
        sat = sat || d > INT32_MAX || d < INT32_MIN;
        const uint64_t magnitude = static_cast<uint64_t>(d < 0 ? -d : d);
        quarter_len2 += magnitude * magnitude / 4;
      }
      saturated += sat ? 1u : 0u;
      const uint64_t quarter_rest2 = static_cast<uint64_t>(int64_t{edge.rest} * edge.rest) / 4;
      (quarter_len2 >= quarter_rest2 ? stretched : compressed) += 1;
    }
  }
  EXPECT_GT(stretched, 100u);
  EXPECT_GT(compressed, 100u);
  EXPECT_GT(idle, 100u);
  EXPECT_GT(saturated, 20u);
}

struct SphereCase {
  std::array<std::vector<int32_t>, 3> position, centre, anchor;
  std::vector<uint32_t> moving;
  int32_t radius = 1;
};

SphereCase make_sphere_case(std::mt19937_64& rng, uint32_t vertices, bool consecutive, uint32_t listed) {
  SphereCase c;
  const uint64_t scale = rng() % 3;
  c.radius = scale == 0 ? 1 + static_cast<int32_t>(rng() % 4)
                        : static_cast<int32_t>(1 + rng() % (scale == 1 ? 100000 : uint64_t{INT32_MAX}));
  for (int a = 0; a < 3; ++a) {
    c.position[a].resize(vertices);
    c.centre[a].resize(vertices);
    c.anchor[a].resize(vertices);
  }
  for (uint32_t v = 0; v < vertices; ++v) {
    const uint64_t kind = rng() % 5;  // 0 at the centre, 1 near the surface, 2 inside, 3 anywhere, 4 far corner
    for (int a = 0; a < 3; ++a) {
      c.centre[a][v] = coordinate(rng);
      c.anchor[a][v] = coordinate(rng);
      int64_t x = c.centre[a][v];
      if (kind == 1) x += (static_cast<int64_t>(c.radius) * (static_cast<int64_t>(rng() % 1201) - 600)) / 1000;
      if (kind == 2) x += static_cast<int64_t>(rng() % (static_cast<uint64_t>(c.radius) / 2 + 1)) - c.radius / 4;
      if (kind == 3) x = coordinate(rng);
      if (kind == 4) x = c.centre[a][v] < 0 ? INT32_MAX : INT32_MIN;
      c.position[a][v] = static_cast<int32_t>(x > INT32_MAX ? INT32_MAX : (x < INT32_MIN ? INT32_MIN : x));
    }
  }
  for (uint32_t v = 0; v < vertices; ++v) c.moving.push_back(v);
  if (!consecutive) std::shuffle(c.moving.begin(), c.moving.end(), rng);
  c.moving.resize(listed);
  return c;
}

std::array<std::vector<int32_t>, 3> collide(ed::RelaxationKernel kernel, const SphereCase& c, uint32_t begin,
                                            uint32_t* moved) {
  std::array<std::vector<int32_t>, 3> position = c.position;
  const ed::SphereJob job{{position[0].data(), position[1].data(), position[2].data()},
                          {c.centre[0].data(), c.centre[1].data(), c.centre[2].data()},
                          {c.anchor[0].data(), c.anchor[1].data(), c.anchor[2].data()},
                          c.moving.data(),
                          c.radius};
  *moved = ed::collide_with_spheres_with(kernel, job, begin, static_cast<uint32_t>(c.moving.size()));
  return position;
}

TEST(RelaxationKernel, CollisionPassWritesTheSpecificationsWords) {
  if (!ed::relaxation_kernel_supported(ed::RelaxationKernel::kAvx512)) GTEST_SKIP() << "no AVX-512 F/VL/CD on this CPU";
  std::mt19937_64 rng(20261208);
  uint64_t moved_total = 0, compared = 0;
  for (int round = 0; round < 400; ++round) {
    const uint32_t vertices = 1 + static_cast<uint32_t>(rng() % 90);
    const bool consecutive = rng() % 2 == 0;
    const uint32_t listed = consecutive ? vertices : 1 + static_cast<uint32_t>(rng() % vertices);
    const SphereCase c = make_sphere_case(rng, vertices, consecutive, listed);
    const uint32_t begin = static_cast<uint32_t>(rng() % 3 == 0 ? rng() % listed : 0);
    uint32_t spec_moved = 0, vec_moved = 0;
    const auto spec = collide(ed::RelaxationKernel::kScalar, c, begin, &spec_moved);
    const auto vec = collide(ed::RelaxationKernel::kAvx512, c, begin, &vec_moved);
    for (int a = 0; a < 3; ++a) ASSERT_EQ(vec[a], spec[a]) << "round " << round << " axis " << a;
    ASSERT_EQ(vec_moved, spec_moved) << "round " << round;
    moved_total += spec_moved;
    compared += listed - begin;
  }
  EXPECT_GT(compared, 8000u);
  EXPECT_GT(moved_total, compared / 5);  // a fifth of the vertices or more are inside
}

}  // namespace
}  // namespace relaxation_kernel_test
