// The runtime pipeline (sim_core/pipeline/pipeline.hpp) on the built-in arm:
// each layer changes the skin inside its support and leaves every vertex
// outside it bit-identical to plain skinning; pose-driven steps read the DOFs
// back from the pose; SPH gains convert with the loop rate; no heap calls.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <set>
#include <span>
#include <vector>

#include "sim_core/pipeline/stage_sph_rate.hpp"
#include "sim_core/skeleton/pose.hpp"
#include "tests/sim_core/barnet/net_oracle.hpp"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/soak.hpp"

namespace pl = sinew::pipeline;
namespace tb = sinew::test::barnet;
using sinew::test::degrees;
using sinew::test::LoadedLayers;

namespace {

constexpr uint32_t kElbowInput = 3;  // shoulder 0..2, elbow 3, twist 4, wrist 5..6; then elbow.force

pl::PipelineOptions only(bool sph, bool metaballs, bool barnet, bool anatomy) {
  pl::PipelineOptions o;
  o.stages.set(pl::Stage::kSph, sph);
  o.stages.set(pl::Stage::kMetaballs, metaballs);
  o.stages.set(pl::Stage::kBarnet, barnet);
  o.stages.set(pl::Stage::kAnatomy, anatomy);
  return o;
}

// Steps the arm `steps` times towards a flexed elbow (with 20 N at the
// wrist) and returns the final positions, SoA.
std::array<std::vector<int32_t>, 3> run(LoadedLayers* arm, const pl::PipelineOptions& o, int steps,
                                        std::span<const uint8_t> measured = {}) {
  std::string error;
  EXPECT_TRUE(arm->start(o, &error)) << error;
  pl::pipeline_set_measured_inputs(&arm->pipeline, measured);
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0);
  for (int s = 1; s <= steps; ++s) {
    inputs[kElbowInput] = degrees(90.0 * s / steps);
    inputs[0] = degrees(20.0 * s / steps);
    inputs[arm->rig.input_count] = 20 * 65536;
    const pl::PipelineStatus st = pl::pipeline_step(&arm->pipeline, inputs);
    EXPECT_TRUE(st.ok()) << st.message;
  }
  std::array<std::vector<int32_t>, 3> out;
  for (int a = 0; a < 3; ++a)
    out[static_cast<size_t>(a)].assign(arm->pipeline.engine.vertices.position[a].begin(),
                                       arm->pipeline.engine.vertices.position[a].end());
  return out;
}

struct Comparison {
  size_t inside_moved = 0, outside_moved = 0;
  double largest_inside_mm = 0;
};

Comparison compare(const LoadedLayers& arm, const std::array<std::vector<int32_t>, 3>& plain,
                   const std::array<std::vector<int32_t>, 3>& layered, const std::set<uint32_t>& support) {
  Comparison c;
  const double mm = std::ldexp(1.0, arm.rig.length_exponent - 20) * 1e3;
  for (uint32_t v = 0; v < arm.rig.vertex_count(); ++v) {
    double d = 0;
    for (size_t a = 0; a < 3; ++a) d = std::max(d, std::abs(static_cast<double>(plain[a][v]) - layered[a][v]));
    if (support.count(v) != 0) {
      c.inside_moved += d > 0 ? 1 : 0;
      c.largest_inside_mm = std::max(c.largest_inside_mm, d * mm);
    } else {
      c.outside_moved += d > 0 ? 1 : 0;
    }
  }
  return c;
}

// Vertices skinned to the shoulder joint alone (the upper arm): an SPH bend
// of the elbow cannot move them.
std::set<uint32_t> not_upper_arm(const LoadedLayers& arm) {
  std::set<uint32_t> s;
  const uint32_t k = arm.rig.influences_per_vertex;
  for (uint32_t v = 0; v < arm.rig.vertex_count(); ++v)
    for (uint32_t i = 0; i < k; ++i)
      if (arm.rig.influence_weight[v * k + i] > 0 && arm.rig.palette[arm.rig.influence_palette[v * k + i]].joint != 0)
        s.insert(v);
  return s;
}

// The arm's limb radius: the built-in arm is a tube about the x axis at
// rest (its joints lie on it), so the largest distance of a rest vertex
// from that axis.
double limb_radius_mm(const LoadedLayers& arm) {
  const double mm = std::ldexp(1.0, arm.rig.length_exponent - 20) * 1e3;
  double r = 0;
  for (uint32_t v = 0; v < arm.rig.vertex_count(); ++v)
    r = std::max(r, std::hypot(static_cast<double>(arm.rig.position[1][v]), arm.rig.position[2][v]) * mm);
  return r;
}

// The net's wrapped skin as eq. (4) puts it (net_oracle.hpp): the wrap of
// the unloaded runtime net's nodes plus D^-1 p in double, per
// wrap entry [w][axis] in Len LSB, with its bound against the runtime.
struct Eq4Skin {
  std::vector<std::array<double, 3>> skin, rest;  // loaded; unloaded (the wrap of s)
  std::vector<double> bound, rest_bound;          // per component
};
Eq4Skin eq4_skin(const tb::NetCheck& n) {
  const sinew::barnet::BarnetModel& m = n.loaded.model();
  const auto exact = tb::eq4_nodes(n.unloaded, n.sys, n.move);
  std::vector<std::vector<double>> still(3, std::vector<double>(m.nodes.size()));
  for (size_t a = 0; a < 3; ++a)
    for (uint32_t k = 0; k < m.nodes.size(); ++k) still[a][k] = n.unloaded.node(a, k);
  Eq4Skin r;
  for (uint32_t w = 0; w < m.wrap.size(); ++w) {
    r.skin.push_back(tb::wrap_oracle(m, exact, w));
    r.rest.push_back(tb::wrap_oracle(m, still, w));
    r.bound.push_back(tb::wrap_bound(m, n.sys.free_count, exact, n.move.bound, w));
    r.rest_bound.push_back(tb::wrap_bound(m, n.sys.free_count, still, 0, w));
  }
  return r;
}

}  // namespace

TEST(Pipeline, BarnetMovesOnlyItsWrappedVertices) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  const auto plain = run(arm.get(), only(false, false, false, false), 20);
  const auto net = run(arm.get(), only(false, false, true, false), 20);
  // The last step's bones and inputs (run: elbow 90 deg, shoulder 20 deg,
  // 20 N on the external input).
  std::vector<int32_t> angles(arm->rig.input_count, 0), external(arm->pipeline.input_count - arm->rig.input_count, 0);
  angles[kElbowInput] = degrees(90.0);
  angles[0] = degrees(20.0);
  external[0] = 20 * 65536;
  const sinew::barnet::BarnetModel& m = arm->layers.barnet.net[0];
  const tb::NetCheck n(m, arm->pipeline.engine.model, angles, external);
  ASSERT_TRUE(n.ok) << n.loaded.error();
  std::set<uint32_t> support;
  for (const auto& w : m.wrap) support.insert(w.vertex);
  const Comparison c = compare(*arm, plain, net, support);
  // The loads raise a bulge: eq. (4)'s move of the wrapped skin from the
  // unloaded net's (the loads' own effect) beyond twice its error bound;
  // and the pipeline's wrapped vertices are the net's, stepped alone on the
  // same bones and inputs (NetCheck's loaded probe, which
  // tests/sim_core/barnet checks against eq. (4) and its wrap), exactly.
  const Eq4Skin e = eq4_skin(n);
  double move = 0, bound = 0;
  int64_t worst_excess = 0;
  for (uint32_t w = 0; w < m.wrap.size(); ++w) {
    bound = std::max(bound, e.bound[w] + e.rest_bound[w]);
    for (size_t a = 0; a < 3; ++a) {
      move = std::max(move, std::abs(e.skin[w][a] - e.rest[w][a]));
      worst_excess =
          std::max<int64_t>(worst_excess, std::llabs(int64_t{net[a][m.wrap[w].vertex]} - n.loaded.skin(a, w)));
    }
  }
  const double mm = std::ldexp(1.0, arm->rig.length_exponent - 20) * 1e3;
  std::printf(
      "bar-net: %zu of %zu wrapped vertices moved (largest %.2f mm), %zu others moved; eq. (4): the loads move the "
      "skin %.2f mm (bound %.2f LSB); the pipeline's skin differs from the net's by %lld LSB\n",
      c.inside_moved, support.size(), c.largest_inside_mm, c.outside_moved, move * mm, bound,
      static_cast<long long>(worst_excess));
  EXPECT_EQ(c.outside_moved, 0u);
  EXPECT_GT(c.inside_moved, support.size() / 4);
  EXPECT_GT(move, 2 * bound) << "the loads raise a bulge at 90 degrees";
  EXPECT_EQ(worst_excess, 0) << "the pipeline's wrapped skin is the net's";
}

TEST(Pipeline, SphMovesItsSkinAndTheDistalBoneOnly) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  const int steps = sinew::test::emulated() ? 10 : 40;
  const auto plain = run(arm.get(), only(false, false, false, false), steps);
  const auto sph = run(arm.get(), only(true, false, false, false), steps);
  std::set<uint32_t> support = not_upper_arm(*arm);
  for (uint32_t v : arm->layers.sph.joint[0].model.skin_vertex) support.insert(v);
  const Comparison c = compare(*arm, plain, sph, support);
  std::printf("sph: %zu of %zu vertices (tissue skin and distal bones) moved (largest %.2f mm), %zu others moved\n",
              c.inside_moved, support.size(), c.largest_inside_mm, c.outside_moved);
  EXPECT_EQ(c.outside_moved, 0u);
  EXPECT_GT(c.inside_moved, 0u);
}

TEST(Pipeline, ElasticSkinMovesOnlyItsSupportRegion) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  const int steps = sinew::test::emulated() ? 4 : 20;
  const auto plain = run(arm.get(), only(false, false, false, false), steps);
  const auto skin = run(arm.get(), only(false, false, false, true), steps);
  ASSERT_FALSE(arm->layers.anatomy.skin_region.empty());
  const std::set<uint32_t> support(arm->layers.anatomy.skin_region.begin(), arm->layers.anatomy.skin_region.end());
  const Comparison c = compare(*arm, plain, skin, support);
  std::printf("elastic skin: %zu of %zu region vertices moved (largest %.2f mm), %zu others moved\n", c.inside_moved,
              support.size(), c.largest_inside_mm, c.outside_moved);
  EXPECT_EQ(c.outside_moved, 0u);
  EXPECT_LT(support.size(), arm->rig.vertex_count()) << "the region is bounded: the hand is far from the biceps";
  EXPECT_GT(c.inside_moved, support.size() / 4);
}

// The metaballs skin is a whole-skin method ([metaballs] covers every
// vertex); it must reshape the skin and stay near it.
TEST(Pipeline, MetaballsReshapeTheWholeSkin) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  const auto plain = run(arm.get(), only(false, false, false, false), 10);
  const auto balls = run(arm.get(), only(false, true, false, false), 10);
  std::set<uint32_t> all;
  for (uint32_t v = 0; v < arm->rig.vertex_count(); ++v) all.insert(v);
  const Comparison c = compare(*arm, plain, balls, all);
  // Stays near it: each vertex stays on its limb, so it moves off plain
  // skinning by less than the limb's diameter, 2 R (R the arm's thickest
  // radius), grown by the largest bulge gain g (balls and their skin
  // displacements scale by at most 1 + g).
  double gain = 0;
  for (const auto& b : arm->layers.metaballs.model.bulges) gain = std::max(gain, std::ldexp(b.gain, -30));
  const double limit = 2 * limb_radius_mm(*arm) * (1 + gain);
  std::printf("metaballs: %zu of %zu vertices moved, largest %.2f mm (bound %.1f mm)\n", c.inside_moved, all.size(),
              c.largest_inside_mm, limit);
  EXPECT_GT(c.inside_moved, all.size() / 2);
  EXPECT_LT(c.largest_inside_mm, limit);
}

// Pose-driven steps (a sampled animation) read each DOF back from the pose:
// the measured values match the commanded ones, and the bar-net's loads
// (activated by the elbow's angle) give the same skin within a fraction of a
// millimetre.
TEST(Pipeline, PoseDrivenStepsMeasureTheDofsTheyCarry) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  std::string error;
  ASSERT_TRUE(arm->start(only(false, false, true, false), &error)) << error;
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0);
  inputs[0] = degrees(30);
  inputs[1] = degrees(-20);
  inputs[kElbowInput] = degrees(100);
  inputs[4] = degrees(45);
  inputs[5] = degrees(-30);
  ASSERT_TRUE(pl::pipeline_step(&arm->pipeline, inputs).ok());
  const std::vector<sinew::skeleton::LocalPose> locals(arm->pipeline.engine.locals.begin(),
                                                       arm->pipeline.engine.locals.end());
  const std::vector<int32_t> commanded(arm->pipeline.engine.vertices.position[1].begin(),
                                       arm->pipeline.engine.vertices.position[1].end());
  ASSERT_TRUE(pl::pipeline_step_locals(&arm->pipeline, locals, {}).ok());
  double worst_deg = 0;
  for (uint32_t d : {0u, kElbowInput, 4u}) {  // single-axis twists of each joint's first DOF
    const double measured = static_cast<double>(arm->pipeline.measured[d]) * 360.0 / 4294967296.0;
    const double wanted = static_cast<double>(inputs[d]) * 360.0 / 4294967296.0;
    if (d != 0) worst_deg = std::max(worst_deg, std::abs(measured - wanted));
  }
  double worst_mm = 0;
  const double mm = std::ldexp(1.0, arm->rig.length_exponent - 20) * 1e3;
  for (uint32_t v = 0; v < arm->rig.vertex_count(); ++v)
    worst_mm = std::max(
        worst_mm, std::abs(static_cast<double>(commanded[v]) - arm->pipeline.engine.vertices.position[1][v]) * mm);
  // Both steps carry the same bones, so plain skinning is the same; the
  // bar-net alone reads DOFs (its loads' activation), and eq. (4) is linear
  // in the loads: the wrapped skin may differ by eq. (4)'s skin for the
  // measured DOFs less that for the commanded ones, plus both runs' bounds
  // against it; every other vertex not at all.
  const sinew::barnet::BarnetModel& m = arm->layers.barnet.net[0];
  const auto rig_inputs = static_cast<std::ptrdiff_t>(arm->rig.input_count);
  const std::vector<int32_t> angles(inputs.begin(), inputs.begin() + rig_inputs),
      external(inputs.begin() + rig_inputs, inputs.end());
  const std::vector<int32_t> measured_angles(arm->pipeline.measured.begin(),
                                             arm->pipeline.measured.begin() + rig_inputs),
      measured_external(arm->pipeline.measured.begin() + rig_inputs, arm->pipeline.measured.end());
  const tb::NetCheck commanded_net(m, arm->pipeline.engine.model, angles, external);
  const tb::NetCheck measured_net(m, arm->pipeline.engine.model, measured_angles, measured_external);
  ASSERT_TRUE(commanded_net.ok && measured_net.ok);
  const Eq4Skin want = eq4_skin(commanded_net), got = eq4_skin(measured_net);
  std::vector<double> allowed(arm->rig.vertex_count(), 0);
  for (uint32_t w = 0; w < m.wrap.size(); ++w)
    allowed[m.wrap[w].vertex] = std::abs(got.skin[w][1] - want.skin[w][1]) + got.bound[w] + want.bound[w];
  double worst_ratio = 0;
  for (uint32_t v = 0; v < arm->rig.vertex_count(); ++v) {
    const double d = std::abs(static_cast<double>(commanded[v]) - arm->pipeline.engine.vertices.position[1][v]);
    if (d > allowed[v]) worst_ratio = std::max(worst_ratio, allowed[v] > 0 ? d / allowed[v] : 1e9);
  }
  std::printf("pose-driven: DOF read back within %.6f deg; skin within %.4f mm of the commanded step\n", worst_deg,
              worst_mm);
  EXPECT_LT(worst_deg, 0.001) << "a single-axis joint's twist is its DOF";
  EXPECT_EQ(worst_ratio, 0) << "the skin moved beyond what the loads' change of activation allows";
}

// SPH gains compiled for 1 kHz, converted for other loop rates
// (sph_gains_for_rate): dt^2 gains scale by rho^2, dt gains by rho, the
// damping's loss by rho; rates needing more than 16 substeps are refused.
TEST(Pipeline, SphGainsConvertWithTheLoopRate) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  const sinew::sph::SphParams& c = arm->layers.sph.joint[0].model.params;
  sinew::sph::SphParams same, slow;
  ASSERT_TRUE(pl::sph_gains_for_rate(c, 1000, 1000, &same).ok());
  EXPECT_EQ(same.elastic_gain, c.elastic_gain);
  ASSERT_TRUE(pl::sph_gains_for_rate(c, 1000, 100, &slow).ok());
  // 1000 Hz x 2 substeps -> 100 Hz x 2 substeps: rho = 10.
  EXPECT_EQ(slow.substeps, 2u);
  EXPECT_NEAR(slow.elastic_gain, 100.0 * c.elastic_gain, 100.0);
  EXPECT_NEAR(slow.pressure_gain, 100.0 * c.pressure_gain, 100.0);
  EXPECT_NEAR(slow.viscosity_gain, 10.0 * c.viscosity_gain, 1.0);
  EXPECT_NEAR(static_cast<double>(sinew::fx::kUnitOne - slow.damping), 10.0 * (sinew::fx::kUnitOne - c.damping), 1.0);
  EXPECT_EQ(slow.tau_f, c.tau_f);
  EXPECT_EQ(slow.h, c.h);
  sinew::sph::SphParams too_slow;
  const pl::PipelineStatus st = pl::sph_gains_for_rate(c, 1000, 5, &too_slow);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(std::string(st.message).find("more than 16 substeps"), std::string::npos) << st.message;
}

TEST(Pipeline, ThousandsOfStepsWithoutAHeapCall) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  std::string error;
  ASSERT_TRUE(arm->start(only(false, true, true, false), &error)) << error;
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0);
  const int steps = sinew::test::emulated() ? 300 : 2000;
  sinew::test::AllocationCounter allocations;
  for (int s = 0; s < steps; ++s) {
    inputs[kElbowInput] = degrees(75.0 + 70.0 * std::sin(s * 0.01));
    ASSERT_TRUE(pl::pipeline_step(&arm->pipeline, inputs).ok());
  }
  std::printf("pipeline (metaballs, bar-net): %llu heap calls in %d steps\n",
              static_cast<unsigned long long>(allocations.allocations()), steps);
  EXPECT_EQ(allocations.allocations(), 0u);
}

TEST(Pipeline, RefusesShortInputsAndTooManyRelaxations) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  std::string error;
  ASSERT_TRUE(arm->start(only(false, false, false, false), &error)) << error;
  std::vector<int32_t> short_inputs(arm->rig.input_count, 0);  // the external force is missing
  EXPECT_EQ(pl::pipeline_step(&arm->pipeline, short_inputs).error, pl::PipelineError::kBadInput);
  pl::PipelineOptions o;
  o.anatomy.skin_iterations = 300;
  EXPECT_FALSE(arm->start(o, &error));
  EXPECT_NE(error.find("skin_iterations"), std::string::npos) << error;
}

// docs/sph.md, "Measured and simulated joints": with the elbow measured, the
// skeleton is the inputs' whatever the load (every joint transform as in
// plain skinning, so every vertex off the SPH tissue too), and the particles
// still move the tissue's skin; with it simulated, the same load bends the
// forearm away from the commanded pose.
TEST(PipelineMeasuredJoint, TheMeasuredElbowAngleIsTheInputs) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  const int steps = sinew::test::emulated() ? 10 : 30;
  const auto plain = run(arm.get(), only(false, false, false, false), steps);
  const std::vector<sinew::fx::Mat34> plain_model(arm->pipeline.engine.model.begin(), arm->pipeline.engine.model.end());
  pl::PipelineOptions measured = only(true, false, false, false);
  measured.sph.joint_measured = true;
  const auto tissue_only = run(arm.get(), measured, steps);
  for (size_t j = 0; j < plain_model.size(); ++j) {
    const sinew::fx::Mat34& a = plain_model[j];
    const sinew::fx::Mat34& b = arm->pipeline.engine.model[j];
    EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << "joint " << j << " moved off the measured pose";
  }
  std::set<uint32_t> tissue(arm->layers.sph.joint[0].model.skin_vertex.begin(),
                            arm->layers.sph.joint[0].model.skin_vertex.end());
  const Comparison c = compare(*arm, plain, tissue_only, tissue);
  std::printf("measured elbow: %zu of %zu tissue vertices moved (largest %.2f mm), %zu others moved\n", c.inside_moved,
              tissue.size(), c.largest_inside_mm, c.outside_moved);
  EXPECT_EQ(c.outside_moved, 0u);
  EXPECT_GT(c.inside_moved, 0u);

  run(arm.get(), only(true, false, false, false), steps);  // simulated: the load bends the forearm
  const uint32_t forearm = arm->layers.sph.joint[0].model.joint.distal_joint;
  const sinew::fx::Mat34& bent = arm->pipeline.engine.model[forearm];
  EXPECT_NE(std::memcmp(&bent, &plain_model[forearm], sizeof bent), 0) << "the simulated joint did not bend";
}

// A source that measures the elbow makes the SPH joint measured by itself
// (sph_joint stays "simulated"): a glove's sensed elbow is the truth under
// load, not a target the particles bend further. With
// sph_measured_from_sources = false (a robot's commanded joint) the same
// load bends the forearm again.
TEST(PipelineMeasuredJoint, AnElbowASourceMeasuresIsNotBentAgain) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  const int steps = sinew::test::emulated() ? 10 : 30;
  run(arm.get(), only(false, false, false, false), steps);
  const uint32_t forearm = arm->layers.sph.joint[0].model.joint.distal_joint;
  const sinew::fx::Mat34 plain = arm->pipeline.engine.model[forearm];
  std::vector<uint8_t> measured(arm->rig.input_count, 0);
  measured[kElbowInput] = 1;
  run(arm.get(), only(true, false, false, false), steps, measured);
  EXPECT_EQ(std::memcmp(&arm->pipeline.engine.model[forearm], &plain, sizeof plain), 0)
      << "the measured elbow was bent by the particles";
  pl::PipelineOptions commanded = only(true, false, false, false);
  commanded.sph.measured_from_sources = false;
  run(arm.get(), commanded, steps, measured);
  EXPECT_NE(std::memcmp(&arm->pipeline.engine.model[forearm], &plain, sizeof plain), 0)
      << "with sph_measured_from_sources = false the commanded elbow did not bend";
}
