// The superposition rule of docs/pipeline.md: out = out + (layer -
// reference), saturated, each clamp counted in Pipeline::saturated. The
// whole-skin loop (add_displacements) against the one-vertex rule
// (add_displacement) on sums at and beyond both int32 ends.
#include <gtest/gtest.h>

#include <climits>
#include <cstdint>
#include <vector>

#include "sim_core/pipeline/pipeline.hpp"
#include "sim_core/pipeline/stage_fns.hpp"

namespace sinew::test {
namespace {

namespace st = pipeline::stages;

struct Skin {
  std::vector<int32_t> out, reference;
};

// The skin's arrays as the pipeline's output and reference on every axis
// (the three views share the skin's vectors).
void bind_skin(Skin& skin, pipeline::Pipeline* p) {
  for (int a = 0; a < 3; ++a) {
    p->engine.vertices.position[a] = skin.out;
    p->reference[a] = skin.reference;
  }
}

TEST(PipelineSuperposition, WholeSkinLoopClampsAndCountsAsTheRule) {
  const std::vector<int32_t> out = {0, INT32_MAX, INT32_MIN, 5, -7, INT32_MAX, INT32_MIN, 100, 1 << 30, -(1 << 30), 3};
  const std::vector<int32_t> layer = {1,         1,    -1,      INT32_MAX,  INT32_MIN, INT32_MAX,
                                      INT32_MIN, -100, 1 << 30, -(1 << 30), 0};
  const std::vector<int32_t> reference = {0,         0, 0,          INT32_MIN, INT32_MAX, INT32_MIN,
                                          INT32_MAX, 0, -(1 << 30), 1 << 30,   3};
  Skin rule{out, reference}, loop{out, reference};
  pipeline::Pipeline by_rule, by_loop;
  bind_skin(rule, &by_rule);
  bind_skin(loop, &by_loop);
  // One axis only: the three views share their vectors.
  for (uint32_t v = 0; v < layer.size(); ++v) st::add_displacement(&by_rule, 0, v, layer[v]);
  st::add_displacements(&by_loop, 0, layer);
  EXPECT_EQ(loop.out, rule.out);
  EXPECT_EQ(by_loop.saturated, by_rule.saturated);
  // Vertices 1 to 6, 8 and 9 leave int32 (by hand: 2^31, -2^31 - 1, ...).
  EXPECT_EQ(by_rule.saturated, 8u);
  EXPECT_EQ(rule.out[1], INT32_MAX);
  EXPECT_EQ(rule.out[2], INT32_MIN);
  EXPECT_EQ(rule.out[7], 0);
  EXPECT_EQ(rule.out[10], 0);
}

// Long skins in the loop's chunks: values at the edge of the plain-sum test
// (|x| = 2^29 passes it, 2^29 + 1 does not) and far beyond it, mixed so that
// some chunks take the plain sums and others the saturating ones.
TEST(PipelineSuperposition, ChunkedLoopAgreesWithTheRuleAtEveryMagnitude) {
  uint64_t rng = 0x5A7u;
  const auto next = [&rng] {
    rng = rng * 6364136223846793005u + 1442695040888963407u;
    return static_cast<uint32_t>(rng >> 33);
  };
  const int32_t edge = int32_t{1} << 29;
  // Below 2^30 in magnitude, yet three of them can sum beyond int32.
  const int32_t near[] = {edge, -edge, edge - 1, edge + 1, -edge - 1, 2 * edge - 1, -2 * edge + 1};
  const int32_t far[] = {INT32_MAX, INT32_MIN, 2 * edge, -2 * edge, 0, 12345};
  for (int round = 0; round < 60; ++round) {
    const size_t n = 1 + next() % 700;
    std::vector<int32_t> out(n), layer(n), reference(n);
    for (size_t v = 0; v < n; ++v) {
      // Whole chunks of one kind: small, near the plain-sum edge, or mixed with the int32 ends.
      const size_t kind = (v / 64 + static_cast<size_t>(round)) % 3;
      for (std::vector<int32_t>* a : {&out, &layer, &reference}) {
        const int32_t small = static_cast<int32_t>(next() % (2u * edge + 1)) - edge;
        (*a)[v] = kind == 0 ? small : kind == 1 ? near[next() % 7] : (next() % 2 ? far[next() % 6] : near[next() % 7]);
      }
    }
    Skin rule{out, reference}, loop{out, reference};
    pipeline::Pipeline by_rule, by_loop;
    bind_skin(rule, &by_rule);
    bind_skin(loop, &by_loop);
    for (uint32_t v = 0; v < n; ++v) st::add_displacement(&by_rule, 0, v, layer[v]);
    st::add_displacements(&by_loop, 0, layer);
    ASSERT_EQ(loop.out, rule.out) << "round " << round;
    ASSERT_EQ(by_loop.saturated, by_rule.saturated) << "round " << round;
  }
}

}  // namespace
}  // namespace sinew::test
