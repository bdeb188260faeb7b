// The [[barnet]] input keys of a TOML rig spec (rigc), compiled, loaded and
// run through the pipeline: force_input and q_input declare their external
// inputs, the BNET section becomes layer version 2 and carries them, the
// ring loads follow the force input instead of the flexion, and a lower q
// from q_input gives a larger bulge (D is linear in q: half the q, twice the
// displacement of every free node, to the rounding of two solves). A net
// without the keys keeps the version-1 section.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "net_oracle.hpp"
#include "spec_rig.hpp"

namespace {

namespace pl = sinew::pipeline;
namespace tb = sinew::test::barnet;
using BarnetRig = tb::SpecRig;

const char* const kPlainSpec = R"(
[rig]
source = "builtin:arm"

[[barnet]]
joint = "elbow"
)";

const char* const kInputSpec = R"(
[rig]
source = "builtin:arm"

[[barnet]]
joint = "elbow"
force_input = "biceps.grip"
force_input_full = 20.0
q_input = "biceps.tone"
)";

// The first net of the rig after its last tick against eq. (4) on the same
// bones and inputs (net_oracle.hpp); its nodes must be the pipeline's.
struct FirstNet {
  explicit FirstNet(BarnetRig& r)
      : check(r.layers.barnet.net[0], r.pipeline.engine.model, r.angles, r.external_values) {
    for (uint32_t i = 0; i < r.layers.barnet.net[0].nodes.size(); ++i)
      for (size_t c = 0; c < 3; ++c) same &= r.pipeline.node_outputs[c][i] == check.loaded.node(c, i);
  }
  // Largest |loaded - unloaded| over the free nodes (Len LSB): the loads' move.
  int32_t loads_move() const {
    int32_t largest = 0;
    for (uint32_t k = 0; k < check.sys.free_count; ++k)
      for (size_t c = 0; c < 3; ++c)
        largest = std::max(largest, std::abs(check.loaded.node(c, check.sys.free_nodes[k]) -
                                             check.unloaded.node(c, check.sys.free_nodes[k])));
    return largest;
  }
  tb::NetCheck check;
  bool same = true;
};

constexpr int32_t kQ16 = 1 << 16;

}  // namespace

TEST(BarnetSpecKeys, PlainNetKeepsTheVersionOneSection) {
  BarnetRig r;
  ASSERT_TRUE(r.compile_and_load(kPlainSpec)) << r.error;
  EXPECT_EQ(r.barnet_section_version(), 1u);
  ASSERT_EQ(r.layers.barnet.count, 1u);
  EXPECT_EQ(r.layers.barnet.net[0].external_count, 0u);
  EXPECT_TRUE(r.layers.barnet.net[0].q_inputs.empty());
  EXPECT_LE(r.step(0, {}), 2) << "no flexion, no load: the bind pose within its rounding (any_rig test)";
  EXPECT_GT(r.step(90, {}), 0) << "the ring loads follow the flexion";
}

TEST(BarnetSpecKeys, ForceAndForceDensityInputsDriveTheNet) {
  BarnetRig r;
  ASSERT_TRUE(r.compile_and_load(kInputSpec)) << r.error;
  EXPECT_EQ(r.barnet_section_version(), sinew::barnet::kBarnetSectionVersion2);
  const uint32_t grip = pl::find_external_input(r.layers, "biceps.grip");
  const uint32_t tone = pl::find_external_input(r.layers, "biceps.tone");
  ASSERT_NE(grip, pl::kNoExternalInput);
  ASSERT_NE(tone, pl::kNoExternalInput);
  EXPECT_EQ(r.layers.external[grip].quantity, static_cast<uint32_t>(pl::InputQuantity::kForce));
  EXPECT_EQ(r.layers.external[tone].quantity, static_cast<uint32_t>(pl::InputQuantity::kScalar));
  const sinew::barnet::BarnetModel& m = r.layers.barnet.net[0];
  EXPECT_EQ(m.external_count, r.layers.external_count());
  ASSERT_FALSE(m.loads.empty());
  for (const sinew::barnet::LoadRecord& l : m.loads) EXPECT_EQ(l.input, r.rig.input_count + grip);
  ASSERT_EQ(m.q_inputs.size(), 1u);
  EXPECT_EQ(m.q_inputs[0].bar_count, m.bars.size());

  std::vector<int32_t> external(r.layers.external_count(), 0);
  external[tone] = kQ16;
  // No grip, no load: flexion alone leaves the net at eq. (4)'s equilibrium
  // under its rest load (the unloaded net, exactly).
  r.step(120, external);
  {
    const FirstNet net(r);
    ASSERT_TRUE(net.check.ok) << net.check.loaded.error();
    EXPECT_EQ(net.loads_move(), 0) << "flexion alone no longer loads the net";
    EXPECT_LE(tb::rest_worst(net.check), net.check.rest.bound);
  }
  // Each state against eq. (4) on the pipeline's bones, inputs and q of the
  // step (scaled_q: q = 1 x 1 and x 1/2, dyadic, so exact), within the
  // rounding bound of net_oracle.hpp.
  struct State {
    int32_t grip, tone;
    int32_t moved = 0;
    double want = 0, bound = 0;
  };
  State states[3] = {{20 * kQ16, kQ16}, {20 * kQ16, kQ16 / 2}, {10 * kQ16, kQ16 / 2}};
  for (State& st : states) {
    external[grip] = st.grip;
    external[tone] = st.tone;
    r.step(0, external);
    const FirstNet net(r);
    st.moved = net.loads_move();
    ASSERT_TRUE(net.check.ok) << net.check.loaded.error();
    EXPECT_TRUE(net.same) << "the pipeline steps the compiled net";
    const double worst = tb::eq4_worst(net.check);
    st.want = net.check.move.largest;
    st.bound = net.check.move.bound;
    std::printf(
        "elbow net, grip %d N, q x %.2f: largest node move %d LSB, eq. (4) %.2f; worst node |runtime - eq. (4)| "
        "%.4f LSB (bound %.4f)\n",
        st.grip / kQ16, st.tone / double(kQ16), st.moved, st.want, worst, st.bound);
    EXPECT_LE(worst, st.bound);
    EXPECT_LE(std::abs(st.moved - st.want), st.bound);
    // The check must tell the loaded net from a still one.
    EXPECT_GT(st.want, 2 * st.bound) << "eq. (4) moves the net beyond the rounding";
  }
  // Figure 3 (d) from the input: D is linear in q, so half the q gives twice
  // the move; each run is within its bound of eq. (4).
  EXPECT_LE(std::abs(states[1].moved - 2.0 * states[0].moved), states[1].bound + 2 * states[0].bound)
      << "half the force density, twice the bulge";
  EXPECT_LE(std::abs(2.0 * states[2].moved - states[1].moved), 2 * states[2].bound + states[1].bound)
      << "the load is linear in the input's value";
}

TEST(BarnetSpecKeys, VersionTwoSectionWithAWrongExternalCountIsRefused) {
  // A version-2 BNET section records how many external inputs its net was
  // built for; a count other than the rig's EXTI count would let a load or
  // a q_inputs record read past the step's external span (or another
  // input), so the loader refuses it and names the field.
  BarnetRig r;
  ASSERT_TRUE(r.compile_and_load(kInputSpec)) << r.error;
  const uint32_t rig_count = r.layers.external_count();
  ASSERT_EQ(rig_count, 2u);
  const size_t field = r.barnet_section_offset() + sizeof(pl::LayerSectionHeader) +
                       offsetof(sinew::barnet::BarnetSectionParams, external_count);
  uint32_t written = 0;
  std::memcpy(&written, r.bytes.data() + field, sizeof(written));
  ASSERT_EQ(written, rig_count) << "the compiled section carries the rig's count";
  const std::vector<uint8_t> good = r.bytes;
  for (const uint32_t wrong : {0u, 1u, 3u, 64u, 0xFFFFFFFFu}) {
    r.bytes = good;
    std::memcpy(r.bytes.data() + field, &wrong, sizeof(wrong));
    r.reseal();
    EXPECT_FALSE(r.load()) << "external_count " << wrong;
    EXPECT_NE(r.error.find("BNET#0.external_count: differs from the rig's external inputs (EXTI)"), std::string::npos)
        << "external_count " << wrong << ": " << r.error;
  }
  r.bytes = good;
  EXPECT_TRUE(r.load()) << r.error;
}

TEST(BarnetSpecKeys, NetKeySelectsThePapersArmNets) {
  // net = "arm-muscles" (Figure 3: 12 free nodes) and "arm-wrinkles"
  // (Figure 6: the fine mesh's vertices) on the built-in arm, through the
  // pipeline: the bind pose leaves the skinned mesh, full flexion moves the
  // net as eq. (4) says (net_oracle.hpp).
  for (const char* net : {"arm-muscles", "arm-wrinkles"}) {
    const std::string text =
        std::string("[rig]\nsource = \"builtin:arm\"\n\n[[barnet]]\njoint = \"elbow\"\nnet = \"") + net + "\"\n";
    BarnetRig r;
    ASSERT_TRUE(r.compile_and_load(text.c_str())) << net << ": " << r.error;
    ASSERT_EQ(r.layers.barnet.count, 1u);
    const sinew::barnet::BarnetModel& m = r.layers.barnet.net[0];
    uint32_t free = 0;
    for (const sinew::barnet::NodeRecord& n : m.nodes) free += n.kind == 0 ? 1u : 0u;
    EXPECT_EQ(free, std::string(net) == "arm-muscles" ? 12u : 77u) << net;
    EXPECT_LE(r.step(0, {}), 2) << net << ": no flexion, no load: the bind pose within its rounding (any_rig test)";
    r.step(150, {});
    const FirstNet check(r);
    const int32_t moved = check.loads_move();
    EXPECT_LE(tb::rest_worst(check.check), check.check.rest.bound) << net << ": the unloaded net";
    ASSERT_TRUE(check.check.ok) << check.check.loaded.error();
    EXPECT_TRUE(check.same) << net;
    const double worst = tb::eq4_worst(check.check);
    std::printf("%s at 150 deg: largest node move %d LSB, eq. (4) %.2f; worst |runtime - eq. (4)| %.4f (bound %.4f)\n",
                net, moved, check.check.move.largest, worst, check.check.move.bound);
    EXPECT_LE(worst, check.check.move.bound) << net;
    EXPECT_LE(std::abs(moved - check.check.move.largest), check.check.move.bound) << net;
    EXPECT_GT(check.check.move.largest, 2 * check.check.move.bound) << net << ": the loads follow the flexion";
  }
  BarnetRig bad;
  EXPECT_FALSE(bad.compile_and_load("[rig]\nsource = \"builtin:arm\"\n\n[[barnet]]\njoint = \"elbow\"\nnet = \"x\"\n"));
  EXPECT_NE(bad.error.find("net must be"), std::string::npos) << bad.error;
}
