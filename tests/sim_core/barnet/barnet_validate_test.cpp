// Bad nets are rejected with a message naming the record and field; bad
// spans at step time change nothing.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "host_tools/layers/barnet/arm_session.hpp"
#include "synthetic_net.hpp"

using namespace sinew::test::barnet;
using sinew::layers::barnet::ArmSession;

namespace {

// A valid copy of the arm's model whose arrays a test may corrupt.
struct Mutable {
  explicit Mutable(const lb::BarnetBuild& b) : build(b) {}
  lb::BarnetBuild build;
  bn::LayerStatus init() {
    const bn::BarnetModel m = build.model();
    const bn::LayerStatus v = bn::barnet_validate_model(m);
    if (!v.ok()) return v;
    std::vector<uint64_t> arena(bn::barnet_state_bytes(m) / 8 + 1, 0);
    bn::BarnetState st;
    return bn::barnet_init(m, arena.data(), arena.size() * 8, &st);
  }
};

void expect_rejected(const bn::LayerStatus& s, bn::LayerError error, const char* fragment) {
  std::printf("barnet rejects: [%s] %s\n", sinew::layer::layer_error_name(s.error), s.message);
  EXPECT_EQ(s.error, error);
  EXPECT_NE(std::strstr(s.message, fragment), nullptr) << "message: " << s.message;
}

}  // namespace

TEST(BarnetValidate, RejectsBadNetsWithAMessage) {
  ArmSession arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  const uint32_t free = arm.state().free_count;
  ASSERT_TRUE(Mutable(arm.build()).init().ok());
  {
    Mutable m(arm.build());  // every node free: no fixed node
    for (auto& n : m.build.nodes) n.kind = 0;
    expect_rejected(m.init(), bn::LayerError::kSingular, "no fixed node");
  }
  {
    Mutable m(arm.build());
    m.build.bars[4].b = 9999;
    expect_rejected(m.init(), bn::LayerError::kBadIndex, "bars[4].b");
  }
  {
    Mutable m(arm.build());
    m.build.bars[2].q = 0;
    expect_rejected(m.init(), bn::LayerError::kBadValue, "bars[2].q: force density must be positive");
  }
  {
    Mutable m(arm.build());
    m.build.bars[3].q = -bn::kForceDensityOne;
    expect_rejected(m.init(), bn::LayerError::kBadValue, "bars[3].q");
  }
  {
    Mutable m(arm.build());
    m.build.bars[5].a = m.build.bars[5].b;
    expect_rejected(m.init(), bn::LayerError::kBadIndex, "two distinct nodes");
  }
  {
    Mutable m(arm.build());
    m.build.loads[1].node = free;  // the first fixed node
    expect_rejected(m.init(), bn::LayerError::kBadIndex, "loads[1].node");
  }
  {
    Mutable m(arm.build());
    m.build.loads[0].input = 200;
    expect_rejected(m.init(), bn::LayerError::kBadIndex, "loads[0].input");
  }
  {
    Mutable m(arm.build());
    m.build.loads[0].angle_hi = m.build.loads[0].angle_lo;
    expect_rejected(m.init(), bn::LayerError::kBadValue, "loads[0].angle_hi");
  }
  {
    Mutable m(arm.build());
    m.build.nodes[7].weight[0] += 1;
    expect_rejected(m.init(), bn::LayerError::kBadValue, "nodes[7].weight");
  }
  {
    Mutable m(arm.build());
    m.build.nodes[3].joint[0] = 77;
    expect_rejected(m.init(), bn::LayerError::kBadIndex, "nodes[3].joint");
  }
  {
    Mutable m(arm.build());
    m.build.nodes[free + 1].kind = 0;  // a free node after the first fixed one
    expect_rejected(m.init(), bn::LayerError::kBadValue, "free nodes must precede");
  }
  {
    Mutable m(arm.build());
    m.build.triangles[0].node[2] = 1000;
    expect_rejected(m.init(), bn::LayerError::kBadIndex, "triangles[0].node");
  }
  {
    Mutable m(arm.build());
    m.build.wrap[10].triangle = 5000;
    expect_rejected(m.init(), bn::LayerError::kBadIndex, "wrap[10].triangle");
  }
  {
    Mutable m(arm.build());
    m.build.wrap[11].bary[1] += 5;
    expect_rejected(m.init(), bn::LayerError::kBadValue, "wrap[11].bary");
  }
  {
    Mutable m(arm.build());
    m.build.wrap[12].vertex = 1u << 30;
    expect_rejected(m.init(), bn::LayerError::kBadIndex, "wrap[12].vertex");
  }
  {
    Mutable m(arm.build());
    m.build.inverse_bind.pop_back();
    expect_rejected(m.init(), bn::LayerError::kBadIndex, "inverse_bind");
  }
}

TEST(BarnetValidate, RejectsAFreeComponentWithoutAPathToAFixedNode) {
  lb::NetSpec s;
  s.nodes = {node(0, 0, 0, true), node(1, 0, 0, false), node(2, 0, 0, false), node(5, 0, 0, false),
             node(6, 0, 0, false)};
  s.bars = {{0, 1, 1.0}, {1, 2, 1.0}, {3, 4, 1.0}};  // nodes 3-4 float
  SyntheticNet net(s);
  std::printf("barnet rejects: %s\n", net.error().c_str());
  EXPECT_FALSE(net.ok());
  EXPECT_NE(net.error().find("no path of bars to a fixed node"), std::string::npos);
}

TEST(BarnetValidate, BuilderRejectsBadSpecs) {
  lb::NetSpec s;
  s.nodes = {node(0, 0, 0, true), node(1, 0, 0, false)};
  s.bars = {{0, 1, -2.0}};
  SyntheticNet bad_q(s);
  std::printf("barnet builder rejects: %s\n", bad_q.error().c_str());
  EXPECT_NE(bad_q.error().find("bars[0].q"), std::string::npos);
  s.bars = {{0, 1, 1.0}};
  s.loads = {{0, 0, 0, 0, 90, {1, 0, 0}}};  // on the fixed node
  SyntheticNet bad_load(s);
  std::printf("barnet builder rejects: %s\n", bad_load.error().c_str());
  EXPECT_NE(bad_load.error().find("loads[0].node"), std::string::npos);
}

TEST(BarnetValidate, StepRejectsShortSpansAndArenaTooSmall) {
  ArmSession arm;
  ASSERT_TRUE(arm.ok()) << arm.error();
  ASSERT_TRUE(arm.step());
  const uint64_t steps = arm.state().stats.steps;
  bn::StepOutputs short_out = arm.outputs();
  short_out.skin[1] = short_out.skin[1].first(10);
  const bn::LayerStatus s = bn::barnet_step(&arm.state(), {arm.engine().model, arm.inputs()}, short_out);
  expect_rejected(s, bn::LayerError::kBadInput, "outputs.skin");
  const std::vector<int32_t> few(1, 0);
  expect_rejected(bn::barnet_step(&arm.state(), {arm.engine().model, few}, arm.outputs()), bn::LayerError::kBadInput,
                  "joint_angles");
  EXPECT_EQ(arm.state().stats.steps, steps);
  std::vector<uint64_t> small(4, 0);
  bn::BarnetState st;
  expect_rejected(bn::barnet_init(arm.model(), small.data(), small.size() * 8, &st), bn::LayerError::kArena, "arena");
}
