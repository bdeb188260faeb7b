// Blobs the loaders accept must be safe to run with every physical layer on.
// The built-in arm is edited so that its core transforms (rest scales and
// translations, inverse binds at +-64), its layer sections' fields (gains,
// iteration counts, stiffnesses, positions, extents, unchecked normals and
// transforms) or both sit at their documented limits; then the whole
// pipeline (SPH with Tresca, metaballs, bar-net, muscles and elastic skin)
// steps on DOF and external inputs at INT32_MIN / INT32_MAX and on extreme
// sampled poses. The dev build (ASan + UBSan, -fno-sanitize-recover) aborts
// on any signed overflow; the outputs must also be the same from a second
// load (no uninitialised reads).
#include "tests/sim_core/pipeline/extreme_layers.hpp"

#include <gtest/gtest.h>

#include <climits>
#include <functional>

#include "host_tools/layers/rig_layers.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/pipeline/stage_sph_rate.hpp"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"
#include "tests/support/soak.hpp"

namespace pl = sinew::pipeline;
namespace t = sinew::test;

namespace {

using Edit = std::function<void(std::vector<uint8_t>*, const sinew::rig::Rig&)>;

constexpr int32_t kInputs[] = {0, INT32_MAX, INT32_MIN, 0x40000000, -0x40000000, 0};

// Steps on every input at each extreme (twice, so the layers' state carries
// the jump), then on alternating extremes, then on sampled poses at the
// extremes; returns every output position.
std::vector<int32_t> run_all_layers(t::LoadedLayers* l) {
  std::string error;
  EXPECT_TRUE(l->start(pl::PipelineOptions{}, &error)) << error;
  if (!error.empty()) return {};
  EXPECT_TRUE(l->pipeline.sph.count > 0 && l->pipeline.metaballs.on && l->pipeline.barnet.count > 0 &&
              l->pipeline.anatomy.on && l->layers.anatomy.has_skin);
  std::vector<int32_t> inputs(l->pipeline.input_count, 0), out;
  uint32_t ticks = 0, ok_ticks = 0;
  const auto record = [&] {
    for (int a = 0; a < 3; ++a)
      out.insert(out.end(), l->pipeline.engine.vertices.position[a].begin(),
                 l->pipeline.engine.vertices.position[a].end());
    out.push_back(static_cast<int32_t>(l->pipeline.saturated));
  };
  for (int32_t v : kInputs)
    for (int rep = 0; rep < 2; ++rep) {
      for (int32_t& in : inputs) in = v;
      // A layer may refuse a tick; undefined behaviour is never allowed.
      ok_ticks += pl::pipeline_step(&l->pipeline, inputs).ok() ? 1u : 0u;
      ++ticks;
      record();
    }
  for (size_t i = 0; i < inputs.size(); ++i) inputs[i] = t::extreme(i, 0);
  ok_ticks += pl::pipeline_step(&l->pipeline, inputs).ok() ? 1u : 0u;
  ++ticks;
  record();
  std::vector<sinew::skeleton::LocalPose> locals(l->rig.joint_count());
  std::vector<int32_t> external(l->layers.external_count(), INT32_MIN);
  for (const int32_t s : {INT32_MAX, INT32_MIN, 1}) {
    for (size_t j = 0; j < locals.size(); ++j)
      locals[j] = {t::extreme_vec(j), {0x20000000, -0x20000000, 0x20000000, 0x20000000}, {s, s, sinew::fx::neg_sat(s)}};
    ok_ticks += pl::pipeline_step_locals(&l->pipeline, locals, external).ok() ? 1u : 0u;
    ++ticks;
    record();
  }
  // Every layer ran: no tick was refused (the force input at its extremes
  // included).
  EXPECT_EQ(ok_ticks, ticks);
  return out;
}

void expect_runs_defined(const Edit& edit) {
  auto arm = t::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  std::vector<uint8_t> bytes = arm->bytes;
  edit(&bytes, arm->rig);
  t::fix_crc(&bytes);
  t::LoadedLayers first, second;
  first.bytes = second.bytes = bytes;
  std::string error;
  ASSERT_TRUE(first.load(&error)) << "every field edited is one the format accepts: " << error;
  ASSERT_TRUE(second.load(&error)) << error;
  const std::vector<int32_t> a = run_all_layers(&first);
  const std::vector<int32_t> b = run_all_layers(&second);
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, b);
}

void push_layers(std::vector<uint8_t>* bytes, bool wide_sph, uint32_t skin_iterations) {
  t::push_sph(bytes, wide_sph);
  t::push_metaballs(bytes);
  t::push_muscles(bytes);
  t::push_skin(bytes, skin_iterations);
  t::push_barnet(bytes);
}

}  // namespace

TEST(ExtremeLayers, RestScaleOfTwoAndAHalfRunsDefined) {
  expect_runs_defined([](std::vector<uint8_t>* b, const sinew::rig::Rig& rig) {
    t::scale_rest(b, rig, 5 << 23);  // 2.5 in Q8.24
  });
}

TEST(ExtremeLayers, ExtremeCoreTransformsRunEveryLayerDefined) { expect_runs_defined(t::push_core_transforms); }

TEST(ExtremeLayers, WideKernelSphAndLayersAtTheirLimitsRunDefined) {
  expect_runs_defined([](std::vector<uint8_t>* b, const sinew::rig::Rig&) { push_layers(b, true, 8); });
}

TEST(ExtremeLayers, NarrowKernelSphAndLayersAtTheirLimitsRunDefined) {
  expect_runs_defined([](std::vector<uint8_t>* b, const sinew::rig::Rig&) { push_layers(b, false, 8); });
}

TEST(ExtremeLayers, EverythingAtItsLimitRunsDefined) {
  expect_runs_defined([](std::vector<uint8_t>* b, const sinew::rig::Rig& rig) {
    t::push_core_transforms(b, rig);
    push_layers(b, false, 8);
  });
  // Many relaxations (without the run time of 256): the sanitizer build is
  // the proof; under qemu (no sanitizer, 10-30x slower) it would take a minute.
  if (sinew::test::emulated()) return;
  expect_runs_defined([](std::vector<uint8_t>* b, const sinew::rig::Rig& rig) {
    t::push_core_transforms(b, rig);
    push_layers(b, true, 64);
  });
}

// The dynamic skin as rigc builds it by default (LEMAN's relaxation), its
// surface terms at their limits (bend 256, 10 kHz reactions, 10^5 N/m^2 of
// air pressure, 200 m/s^2 of gravity), driven by every extreme input and
// pose with every other layer on: defined, and the same from a second load.
TEST(ExtremeLayers, RelaxationSkinWithItsTermsAtTheirLimitsRunsDefined) {
  sinew::rigc::RigSpec spec;
  sinew::layers::LayerSpecs tables;
  ASSERT_TRUE(sinew::rigc::builtin_rig("arm", sinew::rigc::SkinChoice::kDualQuaternion, &spec));
  ASSERT_TRUE(sinew::layers::builtin_layers("arm", &tables));
  auto& solver = tables.anatomy.skin.solver;
  solver.dynamic = true;
  solver.relaxation = true;
  solver.relaxation_iterations = 8;
  solver.bend = 256;
  solver.reaction_frequency = 10000;
  solver.pressure = 1e5;
  solver.gravity[1] = -200;
  std::string error;
  auto arm = t::compiled_with_layers(spec, tables, &error);
  ASSERT_NE(arm, nullptr) << error;
  ASSERT_EQ(arm->layers.anatomy.skin.surface.integrator,
            static_cast<uint8_t>(sinew::elastic_skin::SkinIntegrator::kRelaxation));
  t::LoadedLayers first, second;
  first.bytes = second.bytes = arm->bytes;
  ASSERT_TRUE(first.load(&error)) << error;
  ASSERT_TRUE(second.load(&error)) << error;
  const std::vector<int32_t> a = run_all_layers(&first);
  const std::vector<int32_t> b = run_all_layers(&second);
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, b);
}

TEST(ExtremeLayers, RateConversionOfGainsAtTheirLimitsIsDefined) {
  sinew::sph::SphParams limits;
  limits.h = 1;
  limits.substeps = sinew::sph::kMaxSubsteps;
  limits.elastic_gain = limits.pressure_gain = limits.viscosity_gain = sinew::fx::kUnitOne - 1;
  limits.damping = 1;
  limits.load_gain = INT32_MAX;
  const uint32_t rates[] = {1, 13, 1000, 100000, UINT32_MAX};
  for (uint32_t built : rates)
    for (uint32_t tick : rates) {
      sinew::sph::SphParams out;
      const pl::PipelineStatus st = pl::sph_gains_for_rate(limits, built, tick, &out);
      if (st.ok()) {  // whatever the rates, an accepted conversion keeps every gain in its range
        EXPECT_GE(out.elastic_gain, 0);
        EXPECT_LT(out.elastic_gain, sinew::fx::kUnitOne);
        EXPECT_GE(out.load_gain, 0);
        EXPECT_GE(out.damping, 1);
      }
    }
}
