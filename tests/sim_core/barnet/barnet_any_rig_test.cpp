// The paper's nets on any rig, from a rig spec: [[barnet]] net = "muscles"
// (Figure 3: the flexor and extensor lines of the bone before a joint, 12
// free nodes) and net = "wrinkles" (Figure 6: the skin mesh at a joint's
// fold), on the built-in arm and hand and on the shared glTF models
// (tests/sim_core/barnet/data/*.toml), compiled by rigc and run through the pipeline.
// Oracles (net_oracle.hpp): eq. (4) of the appendix in double for every
// free node on the pipeline's own bones, inputs and force densities of the
// step, and the wrap of eq. (4)'s nodes in double for every bound skin
// vertex; the pipeline's skin must be the engine's plus the nets' wrap,
// exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "golden.hpp"
#include "host_tools/determinism/output_hash.hpp"
#include "net_oracle.hpp"
#include "sim_core/barnet/ldlt_skyline.hpp"
#include "spec_rig.hpp"
#include "tests/support/alloc_guard.hpp"

namespace {

namespace tb = sinew::test::barnet;
namespace bn = sinew::barnet;

const std::string kData = std::string(SINEW_SOURCE_DIR) + "/tests/sim_core/barnet/data/";

const char* const kArmSpec = R"(
[rig]
source = "builtin:arm"
[[barnet]]
joint = "elbow"
net = "muscles"
[[barnet]]
joint = "elbow"
net = "wrinkles"
)";

const char* const kHandSpec = R"(
[rig]
source = "builtin:hand"
[[barnet]]
joint = "middle_pip"
net = "muscles"
[[barnet]]
joint = "index_mcp"
net = "wrinkles"
force_input = "index.push"
)";

struct Case {
  const char* name;
  const char* text;  // builtin spec text, or
  const char* file;  // a spec under tests/sim_core/barnet/data
};

const Case kCases[] = {{"builtin arm", kArmSpec, nullptr},
                       {"builtin hand", kHandSpec, nullptr},
                       {"RiggedFigure.glb", nullptr, "rigged_figure_nets.toml"},
                       {"generic-hand_left.glb", nullptr, "generic_hand_nets.toml"}};

// Compiles the case twice: with its nets, and with the pipeline's bar-nets
// switched off (the skin they displace).
bool compile(const Case& c, tb::SpecRig* on, tb::SpecRig* off) {
  off->options.stages.set(sinew::pipeline::Stage::kBarnet, false);
  for (tb::SpecRig* r : {on, off}) {
    const bool ok = c.text != nullptr ? r->compile_and_load(c.text) : r->compile_file(kData + c.file);
    if (!ok) return false;
  }
  return true;
}

// Inputs activating every load fully: each driving angle or external input
// at its load's upper value (the loads of a net share it).
void full_activation(const tb::SpecRig& r, std::vector<int32_t>* angles, std::vector<int32_t>* external) {
  angles->assign(r.rig.input_count, 0);
  external->assign(r.layers.external_count(), 0);
  for (uint32_t i = 0; i < r.layers.barnet.count; ++i)
    for (const bn::LoadRecord& l : r.layers.barnet.net[i].loads) {
      const bn::BarnetModel& m = r.layers.barnet.net[i];
      if (l.input < m.input_count)
        (*angles)[l.input] = l.angle_hi;
      else
        (*external)[l.input - m.input_count] = l.angle_hi;
    }
}

uint32_t count_free(const bn::BarnetModel& m) {
  uint32_t n = 0;
  for (const bn::NodeRecord& node : m.nodes) n += node.kind == 0 ? 1u : 0u;
  return n;
}

// The solve alone: the loaded step's right-hand side p - (D s + D_f x_f)
// (barnet_step.cpp; its load p in Q.36, s and x_f the skinned nodes) solved
// by the runtime's factor of D against paper_solve of D and the same
// right-hand side in double; largest difference before the final rounding,
// Len LSB.
double solve_error(const tb::NetCheck& n) {
  const bn::BarnetState& st = n.loaded.state();
  const bn::BarnetModel& m = n.loaded.model();
  double worst = 0;
  for (size_t c = 0; c < 3; ++c) {
    const auto skinned = [&](uint32_t i) -> int64_t {
      return i < st.free_count ? st.skinned[c][i] : n.loaded.node(c, i);
    };
    std::vector<int64_t> v(st.free_count);
    for (uint32_t i = 0; i < st.free_count; ++i) v[i] = st.load[c][i];
    for (size_t b = 0; b < m.bars.size(); ++b) {
      const int64_t pull = int64_t{st.q[b]} * (skinned(m.bars[b].a) - skinned(m.bars[b].b));
      if (m.bars[b].a < st.free_count) v[m.bars[b].a] -= pull;
      if (m.bars[b].b < st.free_count) v[m.bars[b].b] += pull;
    }
    std::vector<double> p(st.free_count);
    for (uint32_t i = 0; i < st.free_count; ++i) p[i] = std::ldexp(static_cast<double>(v[i]), -36);
    sinew::fx::Saturation sat;
    bn::ldlt_solve(st.factor, v, sat);
    const std::vector<double> want = tb::paper_solve(n.sys.d, p);
    for (uint32_t i = 0; i < st.free_count; ++i)
      worst = std::max(worst, std::abs(std::ldexp(static_cast<double>(v[i]), -20) - want[i] * tb::kLenLsb));
  }
  return worst;
}

// The pipeline's skin at every vertex is the engine's (the net-less run's)
// plus each net's wrapped position minus it, where the nets wrap it.
int64_t pipeline_mismatches(const tb::SpecRig& on, const tb::SpecRig& off,
                            const std::vector<std::unique_ptr<tb::NetCheck>>& nets) {
  const uint32_t n = on.rig.vertex_count();
  int64_t wrong = 0;
  for (size_t c = 0; c < 3; ++c) {
    const auto& ref = off.pipeline.engine.vertices.position[c];
    std::vector<int64_t> want(ref.begin(), ref.begin() + n);
    for (size_t i = 0; i < nets.size(); ++i) {
      const bn::BarnetModel& m = on.layers.barnet.net[i];
      for (uint32_t w = 0; w < m.wrap.size(); ++w)
        want[m.wrap[w].vertex] += nets[i]->loaded.skin(c, w) - int64_t{ref[m.wrap[w].vertex]};
    }
    for (uint32_t v = 0; v < n; ++v) wrong += on.pipeline.engine.vertices.position[c][v] != want[v] ? 1 : 0;
  }
  return wrong;
}

}  // namespace

TEST(BarnetAnyRig, PapersNetsMoveTheSkinAsEquation4Says) {
  for (const Case& c : kCases) {
    tb::SpecRig on, off;
    ASSERT_TRUE(compile(c, &on, &off)) << c.name << ": " << on.error << off.error;
    ASSERT_GE(on.layers.barnet.count, 2u) << c.name;
    // Bind pose, no input: no activation; the net is eq. (4)'s equilibrium
    // under its rest load (the rig's bind-pose skinning matrices are the
    // identity only up to their rounding, so this is the oracle's, not the
    // rest positions exactly; BarnetArm.BindPoseReproducesTheRestSkin
    // checks those).
    ASSERT_TRUE(on.tick({}, {}));
    for (uint32_t i = 0; i < on.layers.barnet.count; ++i) {
      const tb::NetCheck bind(on.layers.barnet.net[i], on.pipeline.engine.model, on.angles, on.external_values);
      ASSERT_TRUE(bind.ok) << c.name << " net " << i << ": " << bind.loaded.error();
      EXPECT_LE(tb::rest_worst(bind), bind.rest.bound) << c.name << " net " << i << ": bind pose";
    }

    std::vector<int32_t> angles, external;
    full_activation(on, &angles, &external);
    ASSERT_TRUE(on.tick(angles, external) && off.tick(angles, external));
    std::vector<std::unique_ptr<tb::NetCheck>> nets;
    for (uint32_t i = 0; i < on.layers.barnet.count; ++i) {
      const bn::BarnetModel& m = on.layers.barnet.net[i];
      nets.push_back(std::make_unique<tb::NetCheck>(m, on.pipeline.engine.model, on.angles, on.external_values));
      const tb::NetCheck& n = *nets.back();
      ASSERT_TRUE(n.ok) << c.name << " net " << i << ": " << n.loaded.error();
      const bool muscles = m.nodes.size() == 64 && m.loads.size() == 4;
      if (muscles) {
        EXPECT_EQ(count_free(m), 12u) << c.name << ": Figure 3's 12 free nodes";
      }
      // The fixed-point solve of this step's loads against a double solve of
      // the same D and loads: within the bound eq. (4)'s bound assumes.
      const double solve = solve_error(n);
      const double solve_bound =
          tb::solve_bound(n.sys, n.loaded.state().stats.max_displacement + 1.0, n.loaded.state().profile);
      EXPECT_LE(solve, solve_bound) << c.name << " net " << i;
      // Nodes: eq. (4), and the check tells a loaded net from a still one.
      const double worst = tb::eq4_worst(n);
      EXPECT_LE(worst, n.move.bound) << c.name << " net " << i;
      EXPECT_GT(n.move.largest, 2 * n.move.bound) << c.name << " net " << i << ": the loads must move the net";
      // Without loads: eq. (4) under the rest load, the fixed nodes pulling.
      EXPECT_LE(tb::rest_worst(n), n.rest.bound) << c.name << " net " << i << ": the unloaded net";
      // Skin: the wrap of eq. (4)'s nodes; its move from the unloaded
      // net's skin is the wrap of eq. (4)'s move.
      const auto exact = tb::eq4_nodes(n.unloaded, n.sys, n.move);
      std::vector<std::vector<double>> still(3, std::vector<double>(m.nodes.size()));
      for (size_t a = 0; a < 3; ++a)
        for (uint32_t k = 0; k < m.nodes.size(); ++k) still[a][k] = n.unloaded.node(a, k);
      double skin_worst = 0, skin_bound = 0, skin_move = 0;
      for (uint32_t w = 0; w < m.wrap.size(); ++w) {
        const double bound = tb::wrap_bound(m, n.sys.free_count, exact, n.move.bound, w) +
                             tb::wrap_bound(m, n.sys.free_count, still, 0, w);
        const auto want = tb::wrap_oracle(m, exact, w), rest = tb::wrap_oracle(m, still, w);
        for (size_t a = 0; a < 3; ++a) {
          const double got = n.loaded.skin(a, w) - n.unloaded.skin(a, w);
          skin_worst = std::max(skin_worst, std::abs(got - (want[a] - rest[a])) - bound);
          skin_move = std::max(skin_move, std::abs(want[a] - rest[a]));
        }
        skin_bound = std::max(skin_bound, bound);
      }
      const double unit = std::ldexp(1.0, on.rig.length_exponent - 20);  // model units per Len LSB
      std::printf(
          "%s net %u (%s): %zu nodes, %u free, %zu wrapped; largest node move %.3g model units, worst |runtime - "
          "eq. (4)| %.4f LSB (bound %.4f; solve %.2g, bound %.2g); largest skin move %.3g, worst excess over its bound "
          "(%.2f LSB) "
          "%.3f\n",
          c.name, i, muscles ? "muscles" : "wrinkles", m.nodes.size(), n.sys.free_count, m.wrap.size(),
          n.move.largest * unit, worst, n.move.bound, solve, solve_bound, skin_move * unit, skin_bound, skin_worst);
      EXPECT_LE(skin_worst, 0) << c.name << " net " << i << ": the skin must be the wrap of eq. (4)'s nodes";
      EXPECT_GT(skin_move, 2 * skin_bound) << c.name << " net " << i << ": the net must move the skin";
    }
    EXPECT_EQ(pipeline_mismatches(on, off, nets), 0) << c.name << ": the pipeline's skin is the nets' wrap";
  }
}

TEST(BarnetAnyRig, LowerForceDensityFromAnInputGivesALargerBulgeOnAGltfModel) {
  // Figure 3 (d) on RiggedFigure.glb's thigh muscle net (net 0, its q from
  // "thigh.tone"): at full flexion, q x 1/2 moves every free node twice
  // as far as q x 1 (D linear in q), each run within its eq. (4) bound.
  tb::SpecRig r;
  ASSERT_TRUE(r.compile_file(kData + "rigged_figure_nets.toml")) << r.error;
  const uint32_t tone = sinew::pipeline::find_external_input(r.layers, "thigh.tone");
  ASSERT_NE(tone, sinew::pipeline::kNoExternalInput);
  ASSERT_EQ(r.layers.barnet.net[0].q_inputs.size(), 1u);
  std::vector<int32_t> angles, external;
  full_activation(r, &angles, &external);
  double moved[2] = {}, bound[2] = {};
  for (const int half : {0, 1}) {
    external[tone] = half != 0 ? 1 << 15 : 1 << 16;
    ASSERT_TRUE(r.tick(angles, external));
    const tb::NetCheck n(r.layers.barnet.net[0], r.pipeline.engine.model, r.angles, r.external_values);
    ASSERT_TRUE(n.ok) << n.loaded.error();
    EXPECT_LE(tb::eq4_worst(n), n.move.bound);
    EXPECT_EQ(r.pipeline.barnet.net[0].stats.max_displacement, n.loaded.state().stats.max_displacement)
        << "the pipeline's net is the probe's";
    // The loads' move: the loaded net from the unloaded one (both at this q).
    for (uint32_t k = 0; k < n.sys.free_count; ++k)
      for (size_t c = 0; c < 3; ++c)
        moved[half] = std::max<double>(
            moved[half], std::abs(n.loaded.node(c, n.sys.free_nodes[k]) - n.unloaded.node(c, n.sys.free_nodes[k])));
    bound[half] = n.move.bound;
    EXPECT_LE(std::abs(moved[half] - n.move.largest), n.move.bound);
    EXPECT_GT(r.pipeline.barnet.net[0].refactor_products, 0u) << "D re-factorised for this step's q";
  }
  std::printf("RiggedFigure thigh muscles: largest node move %.0f LSB at q, %.0f at q/2\n", moved[0], moved[1]);
  EXPECT_LE(std::abs(moved[1] - 2 * moved[0]), bound[1] + 2 * bound[0]) << "half the force density, twice the bulge";
  EXPECT_GT(moved[0], 2 * bound[0]);
}

TEST(BarnetAnyRig, SkinWithoutVerticesAlongTheBoneIsRefusedNamingTheJoint) {
  // RiggedSimple.glb's skin has vertices at its bones' ends only: no muscle
  // surface along a bone and no vertex whose triangles all lie at a fold.
  for (const char* net : {"muscles", "wrinkles"}) {
    const std::string path = kData + "sinew_refused_net.toml";
    {
      std::ofstream f(path);
      f << "[rig]\nsource = \"../../../data/RiggedSimple.glb\"\n[[barnet]]\njoint = 3\nnet = \"" << net << "\"\n";
    }
    tb::SpecRig r;
    EXPECT_FALSE(r.compile_file(path)) << net;
    std::filesystem::remove(path);
    EXPECT_NE(r.error.find("joint 'node3'"), std::string::npos) << net << ": " << r.error;
    EXPECT_NE(r.error.find(":4: [[barnet]] joint"), std::string::npos) << net << ": " << r.error;
  }
}

TEST(BarnetAnyRig, GltfNetsMatchGoldenAndAllocateNothing) {
  // Every tick's skin and nodes over a trajectory of the driving joints and
  // the external inputs (force and force-density inputs changing every tick,
  // so D is re-factorised each time), hashed; no heap allocation after init.
  for (const auto& [file, golden] : {std::pair{"rigged_figure_nets.toml", tb::golden::kRiggedFigureNets},
                                     std::pair{"generic_hand_nets.toml", tb::golden::kGenericHandNets}}) {
    tb::SpecRig r;
    ASSERT_TRUE(r.compile_file(kData + file)) << r.error;
    std::vector<int32_t> full, full_external;
    full_activation(r, &full, &full_external);
    std::vector<int32_t> inputs(r.rig.input_count + r.layers.external_count(), 0);
    sinew::determinism::OutputHash h;
    sinew::test::AllocationCounter allocations;
    for (int32_t step = 0; step < 120; ++step) {
      const int32_t phase = step % 40 < 20 ? step % 40 : 40 - step % 40;  // 0..20..0
      for (size_t k = 0; k < full.size(); ++k) inputs[k] = full[k] / 20 * phase;
      for (size_t k = 0; k < full_external.size(); ++k)
        inputs[full.size() + k] = full_external[k] != 0 ? full_external[k] / 20 * phase : (1 << 14) * (1 + step % 7);
      ASSERT_TRUE(sinew::pipeline::pipeline_step(&r.pipeline, inputs).ok());
      for (size_t c = 0; c < 3; ++c)
        for (uint32_t v = 0; v < r.rig.vertex_count(); ++v) h.add_i32(r.pipeline.engine.vertices.position[c][v]);
      for (uint32_t i = 0; i < r.layers.barnet.count; ++i) h.add_u32(r.pipeline.barnet.net[i].stats.saturated);
    }
    EXPECT_EQ(allocations.allocations(), 0u) << file;
    // No determinism line: the glTF import runs in the host builds only, and
    // compare-hashes wants every workload in every build; the golden pins
    // each host build (gcc and clang, any level) to the same digest.
    EXPECT_EQ(h.digest(), golden) << file << ": the nets' outputs changed";
  }
}
