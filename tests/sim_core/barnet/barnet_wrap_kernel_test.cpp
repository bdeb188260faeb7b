// The wrap's vector kernels (sim_core/barnet/wrap_avx2.cpp, wrap_avx512.cpp,
// each where the CPU runs it) against the scalar
// specification (wrap.cpp), word for word: on the arm's nets through whole
// steps, and on adversarial control meshes and records (coincident and
// collinear corners, corners at the int32 limits so the edges saturate,
// cross products from 0 to near 2^63, triangle counts that are not a
// multiple of the lane width, records whose sums round beyond int32 so the
// kernel must hand the whole wrap to the specification).
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "host_tools/layers/barnet/arm_session.hpp"
#include "sim_core/barnet/wrap.hpp"

namespace wrap_kernel_test {
namespace {

namespace bn = sinew::barnet;
namespace bd = sinew::barnet::detail;
namespace lb = sinew::layers::barnet;
namespace fx = sinew::fx;

bool avx2_available() { return bn::vector_kernel_supported(bn::VectorKernel::kAvx2); }

// Every vector kernel this CPU runs.
std::vector<bn::VectorKernel> vector_kernels() {
  std::vector<bn::VectorKernel> k;
  for (const bn::VectorKernel v : {bn::VectorKernel::kAvx2, bn::VectorKernel::kAvx512})
    if (bn::vector_kernel_supported(v)) k.push_back(v);
  return k;
}

// A node coordinate: anywhere in int32, near its limits, or small.
int32_t coordinate(std::mt19937_64& rng) {
  switch (rng() % 4) {
    case 0:
      return static_cast<int32_t>(static_cast<uint32_t>(rng()));
    case 1:
      return rng() & 1 ? INT32_MAX - static_cast<int32_t>(rng() % 4) : INT32_MIN + static_cast<int32_t>(rng() % 4);
    case 2:
      return static_cast<int32_t>(rng() % 2001) - 1000;
    default:
      return static_cast<int32_t>(static_cast<int64_t>(rng() >> (34 + rng() % 30)) - (int64_t{1} << (29 - rng() % 29)));
  }
}

struct Mesh {
  std::vector<int32_t> node[3];
  std::vector<bn::NodeRecord> records;  // only their count is read
  std::vector<bn::ControlTriangle> triangles;
  std::span<fx::Len> view[3];
  bn::BarnetModel model;
};

// n nodes at random, some repeated or collinear with others; `count`
// triangles over them.
enum class Spread {
  kAny,        // coordinate()
  kBelow2_30,  // every coordinate below 2^30 in magnitude, many at that limit
               // (edges up to 2^31 - 2 that fit int32 unsaturated)
  kWide,       // uniform within +-1.9 x 2^30: edges beyond int32, no corner at its limits
};

void random_mesh(std::mt19937_64& rng, uint32_t nodes, uint32_t count, Mesh* m, Spread spread = Spread::kAny) {
  constexpr int32_t kLimit = (int32_t{1} << 30) - 1;
  constexpr int64_t kWide = int64_t{19} * (int64_t{1} << 30) / 10;
  for (auto& c : m->node) c.assign(nodes, 0);
  for (uint32_t i = 0; i < nodes; ++i) {
    for (auto& c : m->node) {
      c[i] = coordinate(rng);
      if (spread == Spread::kBelow2_30 && (c[i] > kLimit || c[i] < -kLimit))
        c[i] = rng() & 1 ? kLimit - static_cast<int32_t>(rng() % 3) : -kLimit + static_cast<int32_t>(rng() % 3);
      if (spread == Spread::kWide) c[i] = static_cast<int32_t>(static_cast<int64_t>(rng() % (2 * kWide + 1)) - kWide);
    }
    if (i >= 2 && rng() % 8 == 0) {  // coincident with, or the midpoint of, earlier nodes
      const uint32_t a = static_cast<uint32_t>(rng() % i), b = static_cast<uint32_t>(rng() % i);
      for (auto& c : m->node) c[i] = static_cast<int32_t>((int64_t{c[a]} + c[b]) / 2);
    }
  }
  m->triangles.resize(count);
  for (bn::ControlTriangle& t : m->triangles)
    for (uint32_t& k : t.node) k = static_cast<uint32_t>(rng() % nodes);
  for (size_t c = 0; c < 3; ++c) m->view[c] = m->node[c];
  m->records.resize(nodes);
  m->model.nodes = m->records;
  m->model.triangles = m->triangles;
}

std::vector<int32_t> frame_words(const std::vector<bn::TriangleFrame>& frames) {
  std::vector<int32_t> words;
  for (const bn::TriangleFrame& f : frames) {
    for (const fx::Vec3& v : {f.corner[0], f.corner[1], f.corner[2], f.normal})
      words.insert(words.end(), {v.x, v.y, v.z});
    words.push_back(f.pad);
  }
  return words;
}

// A step's words: nodes, wrapped skin and the triangle frames.
std::vector<int32_t> step_words(lb::ArmSession& s) {
  std::vector<int32_t> words;
  for (size_t c = 0; c < 3; ++c) {
    words.insert(words.end(), s.outputs().node[c].begin(), s.outputs().node[c].end());
    words.insert(words.end(), s.outputs().skin[c].begin(), s.outputs().skin[c].end());
  }
  const std::vector<bn::TriangleFrame> frames(s.state().triangle.begin(), s.state().triangle.end());
  const std::vector<int32_t> f = frame_words(frames);
  words.insert(words.end(), f.begin(), f.end());
  return words;
}

std::vector<int32_t> frames_by(const Mesh& m, bn::VectorKernel kernel) {
  // One frame more than the triangles: a kernel must leave it as it was.
  std::vector<bn::TriangleFrame> frames(m.triangles.size() + 1);
  for (bn::TriangleFrame& f : frames) f = {{{7, 7, 7}, {7, 7, 7}, {7, 7, 7}}, {7, 7, 7}, 7};  // overwritten by all
  std::span<fx::Len> node[3] = {m.view[0], m.view[1], m.view[2]};
  bd::make_triangle_frames(m.model, node, std::span(frames).first(m.triangles.size()), kernel);
  const std::vector<int32_t> beyond = frame_words({frames.back()});
  EXPECT_EQ(beyond, std::vector<int32_t>(beyond.size(), 7)) << "a word past the last frame was written";
  frames.pop_back();
  return frame_words(frames);
}

}  // namespace
}  // namespace wrap_kernel_test

using namespace wrap_kernel_test;

TEST(BarnetWrapKernel, ArmNetsStepToTheSpecificationsWords) {
  if (!avx2_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  for (const int segments : {8, 16, 32}) {
    lb::ArmNetOptions o;
    o.segments = segments;
    lb::ArmSession vector(sinew::rigc::SkinChoice::kLinear, o), scalar(sinew::rigc::SkinChoice::kLinear, o);
    ASSERT_TRUE(vector.ok() && scalar.ok()) << vector.error() << scalar.error();
    ASSERT_EQ(vector.state().kernel, vector_kernels().back()) << "init picks the fastest kernel the CPU runs";
    scalar.state().kernel = bn::VectorKernel::kScalar;
    for (const double degrees : {0.0, 30.0, 90.0, 150.0}) {
      for (lb::ArmSession* s : {&vector, &scalar}) {
        s->inputs()[static_cast<size_t>(s->input("elbow.0"))] = lb::degrees_to_angle(degrees);
        ASSERT_TRUE(s->step()) << s->error();
      }
      EXPECT_EQ(step_words(vector), step_words(scalar)) << segments << " segments at " << degrees << " deg";
      EXPECT_EQ(vector.state().stats.saturated, scalar.state().stats.saturated);
    }
  }
}

TEST(BarnetWrapKernel, TriangleFramesMatchOnAdversarialMeshes) {
  if (!avx2_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  std::mt19937_64 rng(20261204);
  uint32_t degenerate = 0, saturated_edges = 0, long_unsaturated_edges = 0;
  for (int trial = 0; trial < 1200; ++trial) {
    Mesh m;  // trials 1, 4, 7, ...: every node below 2^30, the kernel's unsaturated edges
    const Spread spread = trial % 3 == 0 ? Spread::kAny : (trial % 3 == 1 ? Spread::kBelow2_30 : Spread::kWide);
    random_mesh(rng, 3 + static_cast<uint32_t>(rng() % 12), static_cast<uint32_t>(trial % 11), &m, spread);
    const std::vector<int32_t> expected = frames_by(m, bn::VectorKernel::kScalar);
    for (const bn::VectorKernel kernel : vector_kernels())
      ASSERT_EQ(frames_by(m, kernel), expected) << "trial " << trial << " kernel " << static_cast<int>(kernel);
    for (size_t t = 0; t < m.triangles.size(); ++t) {
      const int32_t* n = &expected[13 * t + 9];
      degenerate += n[0] == 0 && n[1] == 0 && n[2] == 0 ? 1u : 0u;
      const fx::Vec3 a{m.node[0][m.triangles[t].node[0]], m.node[1][m.triangles[t].node[0]],
                       m.node[2][m.triangles[t].node[0]]};
      const fx::Vec3 b{m.node[0][m.triangles[t].node[1]], m.node[1][m.triangles[t].node[1]],
                       m.node[2][m.triangles[t].node[1]]};
      saturated_edges += int64_t{b.x} - a.x != fx::sub(b, a).x ? 1u : 0u;
      long_unsaturated_edges +=
          spread == Spread::kBelow2_30 && fx::magnitude(int64_t{b.x} - a.x) > (uint64_t{1} << 31) - 8;
    }
  }
  // The cases the kernel must get right were drawn.
  EXPECT_GT(degenerate, 20u);
  EXPECT_GT(saturated_edges, 20u);
  EXPECT_GT(long_unsaturated_edges, 20u);
}

TEST(BarnetWrapKernel, BoundedWrapMatchesAndHandsOverflowToTheSpecification) {
  if (!avx2_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  std::mt19937_64 rng(4242);
  uint32_t trials_with_saturation = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Mesh m;
    random_mesh(rng, 12, 1 + static_cast<uint32_t>(rng() % 9), &m);
    std::vector<bn::TriangleFrame> frames(m.triangles.size());
    bd::make_triangle_frames(m.model, m.view, frames, bn::VectorKernel::kScalar);
    // Records within the bounded path's limits (|b0| + |b1| + |b2| <= 2^31,
    // |d| <= 2^30, the barycentres summing to 2^30), near and inside the
    // triangle or far outside; in a third of the trials only small corners,
    // so that nothing saturates and the kernel's own words are compared.
    const bool small = trial % 3 == 0;
    if (small)
      for (bn::TriangleFrame& f : frames)
        for (fx::Vec3& c : f.corner) c = {c.x >> 12, c.y >> 12, c.z >> 12};
    std::vector<bn::WrapRecord> wrap(1 + rng() % 23);
    for (bn::WrapRecord& r : wrap) {
      r.triangle = static_cast<uint32_t>(rng() % frames.size());
      const int64_t spread = rng() & 1 ? (int64_t{1} << 30) : (int64_t{1} << 29);
      const int64_t b0 = static_cast<int64_t>(rng() % static_cast<uint64_t>(spread)) - spread / 4;
      const int64_t b1 = static_cast<int64_t>(rng() % static_cast<uint64_t>(spread)) - spread / 4;
      r.bary[0] = static_cast<int32_t>(b0), r.bary[1] = static_cast<int32_t>(b1);
      r.bary[2] = static_cast<int32_t>(fx::kUnitOne - b0 - b1);
      r.offset = static_cast<int32_t>(static_cast<int64_t>(rng() % (uint64_t{1} << 31)) - (int64_t{1} << 30));
    }
    m.model.wrap = wrap;
    std::vector<int32_t> expected[3], got[3];
    for (size_t c = 0; c < 3; ++c) expected[c].assign(wrap.size(), 0);
    std::span<fx::Len> expected_view[3] = {expected[0], expected[1], expected[2]};
    std::span<fx::Len> got_view[3];
    fx::Saturation expected_sat;
    bd::wrap_vertices(m.model, frames, true, expected_view, expected_sat, bn::VectorKernel::kScalar);
    for (const bn::VectorKernel kernel : vector_kernels()) {
      for (size_t c = 0; c < 3; ++c) got[c].assign(wrap.size(), 0), got_view[c] = got[c];
      fx::Saturation got_sat;
      bd::wrap_vertices(m.model, frames, true, got_view, got_sat, kernel);
      for (size_t c = 0; c < 3; ++c) ASSERT_EQ(got[c], expected[c]) << "trial " << trial << " axis " << c;
      ASSERT_EQ(got_sat.events, expected_sat.events) << "trial " << trial;
    }
    if (small) {
      ASSERT_EQ(expected_sat.events, 0u) << "trial " << trial;
#if defined(__x86_64__)
      EXPECT_TRUE(bd::wrap_bounded_avx2(m.model, frames, got_view)) << "trial " << trial;
#endif
    }
    trials_with_saturation += expected_sat.events > 0 ? 1u : 0u;
  }
  EXPECT_GT(trials_with_saturation, 30u) << "the hand-over to the specification was exercised";
}
