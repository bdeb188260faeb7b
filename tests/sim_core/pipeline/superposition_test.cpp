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

TEST(PipelineSuperposition, WholeSkinLoopClampsAndCountsAsTheRule) {
  const std::vector<int32_t> out = {0, INT32_MAX, INT32_MIN, 5, -7, INT32_MAX, INT32_MIN, 100, 1 << 30, -(1 << 30), 3};
  const std::vector<int32_t> layer = {1,         1,    -1,      INT32_MAX,  INT32_MIN, INT32_MAX,
                                      INT32_MIN, -100, 1 << 30, -(1 << 30), 0};
  const std::vector<int32_t> reference = {0,         0, 0,          INT32_MIN, INT32_MAX, INT32_MIN,
                                          INT32_MAX, 0, -(1 << 30), 1 << 30,   3};
  Skin rule{out, reference}, loop{out, reference};
  pipeline::Pipeline by_rule, by_loop;
  for (int a = 0; a < 3; ++a) {
    by_rule.engine.vertices.position[a] = rule.out;
    by_rule.reference[a] = rule.reference;
    by_loop.engine.vertices.position[a] = loop.out;
    by_loop.reference[a] = loop.reference;
  }
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

}  // namespace
}  // namespace sinew::test
