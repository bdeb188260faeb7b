// The static relaxation's moving vertices (SkinModel::region,
// skin_state.hpp): the region and the vertices within kHaloRings edges of
// it, found here by an independent breadth-first search; the edges with a
// moving end; the held ends of those edges mapped and on their anchors
// through every step (the vertices beyond are never read); every
// vertex without a region or in dynamic mode; a region that is not
// ascending within the skin rejected by name.
#include <gtest/gtest.h>

#include <deque>
#include <vector>

#include "tests/sim_core/muscle/anatomy_fixture.hpp"

namespace es = sinew::elastic_skin;

namespace skin_moving_test {

struct OwnState {
  std::vector<uint64_t> memory;
  es::SkinState state;
  es::LayerStatus init(const es::SkinModel& model) {
    memory.assign(es::skin_state_bytes(model) / 8 + 1, 0);
    return es::skin_init(model, memory.data(), memory.size() * 8, &state);
  }
};

// Ring distance from the region over the skin's edges (breadth first).
std::vector<uint32_t> rings_from(const es::SkinModel& model, const std::vector<uint32_t>& region) {
  std::vector<std::vector<uint32_t>> next(model.vertex_count);
  for (const es::Edge& e : model.edges) next[e.a].push_back(e.b), next[e.b].push_back(e.a);
  std::vector<uint32_t> ring(model.vertex_count, UINT32_MAX);
  std::deque<uint32_t> queue;
  for (uint32_t v : region) ring[v] = 0, queue.push_back(v);
  while (!queue.empty()) {
    const uint32_t v = queue.front();
    queue.pop_front();
    for (uint32_t w : next[v])
      if (ring[w] == UINT32_MAX) ring[w] = ring[v] + 1, queue.push_back(w);
  }
  return ring;
}

TEST(SkinMoving, TheRegionAndItsHaloMoveTheRestStayOnTheirAnchors) {
  sinew::test::ArmAnatomy arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  es::SkinModel model = arm.skin_model();
  // Every third vertex of the skin's first half: a region with holes and a border.
  std::vector<uint32_t> region;
  for (uint32_t v = 0; v < model.vertex_count / 2; v += 3) region.push_back(v);
  model.region = region;
  OwnState own;
  ASSERT_TRUE(own.init(model).ok());
  const es::SkinState& s = own.state;
  const std::vector<uint32_t> ring = rings_from(model, region);
  std::vector<uint32_t> expected;
  for (uint32_t v = 0; v < model.vertex_count; ++v)
    if (ring[v] <= es::kHaloRings) expected.push_back(v);
  ASSERT_LT(expected.size(), model.vertex_count);  // some vertices are held
  ASSERT_EQ(s.moving_vertices, expected.size());
  for (uint32_t k = 0; k < s.moving_vertices; ++k) ASSERT_EQ(s.moving_vertex[k], expected[k]);
  uint32_t edges = 0;
  for (uint32_t e = 0; e < model.edges.size(); ++e) {
    if (ring[model.edges[e].a] > es::kHaloRings && ring[model.edges[e].b] > es::kHaloRings) continue;
    ASSERT_LT(edges, s.moving_edges);
    ASSERT_EQ(s.moving_edge[edges], e);
    ++edges;
  }
  EXPECT_EQ(edges, s.moving_edges);
  // Mapped: the moving vertices and the held ends of their edges, one ring out.
  std::vector<uint32_t> mapped;
  for (uint32_t v = 0; v < model.vertex_count; ++v)
    if (ring[v] <= es::kHaloRings + 1) mapped.push_back(v);
  ASSERT_LT(mapped.size(), model.vertex_count);
  ASSERT_EQ(s.mapped_vertices, mapped.size());
  for (uint32_t k = 0; k < s.mapped_vertices; ++k) ASSERT_EQ(s.mapped_vertex[k], mapped[k]);

  uint32_t moved_off_anchor = 0;
  for (int step = 0; step < 12; ++step) {
    arm.set("elbow.0", 20.0 + 8.0 * step);
    ASSERT_TRUE(arm.step_muscles().ok());
    ASSERT_TRUE(
        es::skin_step(model, arm.muscle_model(), arm.muscles(), arm.engine().model, es::SkinTick{}, &own.state).ok());
    for (uint32_t v = 0; v < model.vertex_count; ++v) {
      const bool off = s.position[0][v] != s.anchor[0][v] || s.position[1][v] != s.anchor[1][v] ||
                       s.position[2][v] != s.anchor[2][v];
      if (ring[v] == es::kHaloRings + 1) {  // held, its anchor mapped: the moving edges read it
        ASSERT_FALSE(off) << "held vertex " << v << " left its anchor at step " << step;
        ASSERT_NE(s.anchor[0][v] | s.anchor[1][v] | s.anchor[2][v], 0) << "held vertex " << v << " not mapped";
      } else if (ring[v] <= es::kHaloRings) {
        moved_off_anchor += off ? 1 : 0;
      }
    }
  }
  EXPECT_GT(moved_off_anchor, 0u);
}

TEST(SkinMoving, EveryVertexWithoutARegionOrInDynamicMode) {
  sinew::test::ArmAnatomy arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  es::SkinModel model = arm.skin_model();
  OwnState whole;
  ASSERT_TRUE(whole.init(model).ok());
  EXPECT_EQ(whole.state.moving_vertices, model.vertex_count);
  EXPECT_EQ(whole.state.moving_edges, model.edges.size());
  const std::vector<uint32_t> region = {1, 5, 9};
  model.region = region;
  model.solver.mode = static_cast<uint8_t>(es::SkinMode::kDynamic);
  OwnState dynamic;
  ASSERT_TRUE(dynamic.init(model).ok());
  EXPECT_EQ(dynamic.state.moving_vertices, model.vertex_count);
}

TEST(SkinMoving, ARegionNotAscendingWithinTheSkinIsRejected) {
  sinew::test::ArmAnatomy arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  es::SkinModel model = arm.skin_model();
  for (const std::vector<uint32_t>& bad :
       {std::vector<uint32_t>{3, 2}, std::vector<uint32_t>{4, 4}, std::vector<uint32_t>{0, model.vertex_count}}) {
    model.region = bad;
    OwnState own;
    const es::LayerStatus st = own.init(model);
    EXPECT_FALSE(st.ok());
    EXPECT_NE(std::string(st.message).find("region"), std::string::npos) << st.message;
  }
}

}  // namespace skin_moving_test
