// The dynamic elastic skin through rigc and the board's loader: a [skin]
// mode = "dynamic" rig writes a version 2 SKIN section, loads with its
// solver record, and steps in the pipeline at the loop's rate; a static
// rig keeps its version 1 section.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>

#include "host_tools/layers/rig_layers.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "tests/sim_core/elastic_skin/relaxation_oracle.hpp"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"

namespace pl = sinew::pipeline;

namespace {

// The built-in arm with the dynamic skin; `tweak` may edit its layer tables.
template <typename Tweak>
std::unique_ptr<sinew::test::LoadedLayers> arm_with_dynamic_skin(std::string* error, Tweak tweak) {
  sinew::rigc::RigSpec spec;
  sinew::layers::LayerSpecs layers;
  if (!sinew::rigc::builtin_rig("arm", sinew::rigc::SkinChoice::kDualQuaternion, &spec) ||
      !sinew::layers::builtin_layers("arm", &layers))
    return nullptr;
  layers.anatomy.skin.solver.dynamic = true;
  layers.anatomy.skin.solver.relaxation = false;  // the explicit integrator's substeps and section versions
  tweak(layers);
  return sinew::test::compiled_with_layers(std::move(spec), layers, error);
}

std::unique_ptr<sinew::test::LoadedLayers> arm_with_dynamic_skin(std::string* error) {
  return arm_with_dynamic_skin(error, [](sinew::layers::LayerSpecs& l) { l.anatomy.skin.solver.gravity[1] = -9.81; });
}

uint32_t skin_section_version(const std::vector<uint8_t>& bytes) {
  const size_t at = sinew::test::section_offset(bytes, sinew::elastic_skin::kSectionElasticSkin);
  uint32_t v = 0;
  if (at != 0) std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

}  // namespace

TEST(SkinDynamicPipeline, StaticRigKeepsVersion1) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  EXPECT_EQ(skin_section_version(arm->bytes), 1u);
  EXPECT_EQ(arm->layers.anatomy.skin.solver.mode, static_cast<uint8_t>(sinew::elastic_skin::SkinMode::kStatic));
}

TEST(SkinDynamicPipeline, DynamicRigLoadsAndStepsAtTheLoopRate) {
  std::string error;
  auto arm = arm_with_dynamic_skin(&error);
  ASSERT_NE(arm, nullptr) << error;
  EXPECT_EQ(skin_section_version(arm->bytes), sinew::elastic_skin::kSkinSectionVersion2);
  const sinew::elastic_skin::SkinSolverParams& solver = arm->layers.anatomy.skin.solver;
  EXPECT_EQ(solver.mode, static_cast<uint8_t>(sinew::elastic_skin::SkinMode::kDynamic));
  EXPECT_LT(solver.gravity.y, 0);
  pl::PipelineOptions options;
  options.tick_hz = 500;
  ASSERT_TRUE(arm->start(options, &error)) << error;
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0);
  // 100 ticks (0.2 s; substeps of the whole arm skin each, slow under
  // ASan and qemu): the first DOF turns 90 degrees in 0.1 s, then stops.
  for (int k = 0; k < 100; ++k) {
    inputs[0] = sinew::test::degrees(k < 50 ? k * 1.8 : 90.0);
    const pl::PipelineStatus st = pl::pipeline_step(&arm->pipeline, inputs);
    ASSERT_TRUE(st.ok()) << st.message;
    ASSERT_EQ(arm->pipeline.anatomy.skin.stats.substeps, (solver.substep_hz + 499) / 500);  // ceil(substep_hz / 500)
    ASSERT_EQ(arm->pipeline.anatomy.skin.stats.inside_after, 0u) << "tick " << k;
  }
}

namespace {

// The built-in arm with the dynamic skin, no gravity, and the base's
// acceleration read from three external inputs.
std::unique_ptr<sinew::test::LoadedLayers> arm_on_a_moving_base(std::string* error) {
  return arm_with_dynamic_skin(error, [](sinew::layers::LayerSpecs& l) {
    l.anatomy.skin.base_acceleration = {"base.ax", "base.ay", "base.az"};
  });
}

// Every skin vertex of `steps` ticks at 1 kHz: the elbow swings 40 degrees
// in the first 0.1 s and stops; `extra` fills the inputs after the rig's.
std::vector<int32_t> run_skin(sinew::test::LoadedLayers* arm, const std::vector<int32_t>& extra, int steps) {
  pl::PipelineOptions options;
  options.tick_hz = 1000;
  std::string error;
  EXPECT_TRUE(arm->start(options, &error)) << error;
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0);
  std::copy(extra.begin(), extra.end(), inputs.begin() + static_cast<std::ptrdiff_t>(arm->rig.input_count));
  std::vector<int32_t> out;
  for (int k = 0; k < steps; ++k) {
    inputs[0] = sinew::test::degrees(k < 100 ? k * 0.4 : 40.0);
    const pl::PipelineStatus st = pl::pipeline_step(&arm->pipeline, inputs);
    EXPECT_TRUE(st.ok()) << st.message;
  }
  for (int a = 0; a < 3; ++a)
    out.insert(out.end(), arm->pipeline.anatomy.skin.position[a].begin(), arm->pipeline.anatomy.skin.position[a].end());
  return out;
}

}  // namespace

TEST(SkinDynamicPipeline, BaseAccelerationInputsReachTheSkinAsAnInertialField) {
  // LEMAN §3 in the frame the bones are given in: the skin feels
  // gravity - a_base. A base accelerating at +a along y (fed through the
  // three inputs, m/s^2) must move the skin exactly as gravity of -a with a
  // resting base: the same field, bit for bit.
  std::string error;
  auto moving = arm_on_a_moving_base(&error);
  ASSERT_NE(moving, nullptr) << error;
  EXPECT_EQ(skin_section_version(moving->bytes), sinew::elastic_skin::kSkinSectionVersion5);
  for (int c = 0; c < 3; ++c) ASSERT_NE(moving->layers.anatomy.skin_base_acceleration[c], pl::kNoExternalInput);
  const uint32_t ay = moving->layers.anatomy.skin_base_acceleration[1];
  EXPECT_EQ(moving->layers.external[ay].quantity, static_cast<uint32_t>(pl::InputQuantity::kAcceleration));
  // 4 m/s^2 in Q16.16; on the arm (metres, length_exponent 0) 1024 in Q24.8.
  std::vector<int32_t> extra(moving->layers.external_count(), 0);
  extra[ay] = 4 << 16;
  const std::vector<int32_t> accelerated = run_skin(moving.get(), extra, 300);

  auto heavy =
      arm_with_dynamic_skin(&error, [](sinew::layers::LayerSpecs& l) { l.anatomy.skin.solver.gravity[1] = -4.0; });
  ASSERT_NE(heavy, nullptr) << error;
  const std::vector<int32_t> under_gravity = run_skin(heavy.get(), {}, 300);
  EXPECT_EQ(accelerated, under_gravity);

  // And the field is felt: at rest on the same motion the skin ends elsewhere
  // (the anchors' springs hold each vertex m a / k away from its anchor).
  std::fill(extra.begin(), extra.end(), 0);
  auto resting = arm_on_a_moving_base(&error);
  ASSERT_NE(resting, nullptr) << error;
  EXPECT_NE(run_skin(resting.get(), extra, 300), accelerated);
}

// The same claim against an independent implementation: the arm's LEMAN
// skin (the relaxation integrator) through the pipeline, its base
// accelerating at +4 m/s^2 along y through the three inputs, steps like the
// double oracle of the step (relaxation_oracle.hpp) whose field is
// gravity - a_base = -4 m/s^2, from the runtime's state each tick. An
// oracle with no field parts from it by far more: the inputs must act.
TEST(SkinDynamicPipeline, BaseAccelerationActsInTheEquationOfMotionAsTheOracleSays) {
  std::string error;
  auto arm = arm_with_dynamic_skin(&error, [](sinew::layers::LayerSpecs& l) {
    l.anatomy.skin.solver.relaxation = true;
    l.anatomy.skin.base_acceleration = {"base.ax", "base.ay", "base.az"};
  });
  ASSERT_NE(arm, nullptr) << error;
  const sinew::elastic_skin::SkinModel& model = arm->layers.anatomy.skin;
  ASSERT_EQ(model.surface.integrator, static_cast<uint8_t>(sinew::elastic_skin::SkinIntegrator::kRelaxation));
  pl::PipelineOptions options;
  options.tick_hz = 1000;
  *pl::anatomy_skin_max_anchor_acceleration_option(&options) = 0;  // no carrying: the oracle has none
  ASSERT_TRUE(arm->start(options, &error)) << error;
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0);
  const uint32_t ay = arm->layers.anatomy.skin_base_acceleration[1];
  inputs[arm->rig.input_count + ay] = 4 << 16;  // m/s^2, Q16.16
  sinew::test::RelaxationOracle with_field(model), without(model);
  // Rig units / s^2: one rig unit is 2^e metres.
  with_field.gravity = {0, -4.0 * std::ldexp(1.0, -arm->rig.length_exponent), 0};
  without.gravity = {0, 0, 0};
  const sinew::elastic_skin::SkinState& s = arm->pipeline.anatomy.skin;
  const auto& m = arm->pipeline.anatomy.muscles;
  double worst = 0, apart = 0;
  for (int k = 0; k < 150; ++k) {
    inputs[0] = sinew::test::degrees(k < 100 ? k * 0.4 : 40.0);
    const bool compare = k > 0;  // the first step settles the skin statically
    if (compare) with_field.start(s), without.start(s);
    const pl::PipelineStatus st = pl::pipeline_step(&arm->pipeline, inputs);
    ASSERT_TRUE(st.ok()) << st.message;
    if (!compare) continue;
    const sinew::test::OracleInputs in = sinew::test::oracle_inputs(s, m, with_field.band_vertex.size());
    ASSERT_TRUE(in.supported) << "a primitive the oracle does not model";
    with_field.step(1e-3, in.anchors, in.normals, in.targets, in.prims, &in.decided, in.threshold);
    without.step(1e-3, in.anchors, in.normals, in.targets, in.prims, &in.decided, in.threshold);
    for (size_t i = 0; i < with_field.n; ++i) {
      sinew::test::V3 d{}, e{};
      for (size_t c = 0; c < 3; ++c) {
        d[c] = sinew::test::len_units(s.position[c][i]) - with_field.x[i][c];
        e[c] = sinew::test::len_units(s.position[c][i]) - without.x[i][c];
      }
      worst = std::max(worst, sinew::test::norm3(d));
      apart = std::max(apart, sinew::test::norm3(e));
    }
  }
  // The one-step bound of the arm oracle test (2 LSB a sweep + 2), plus
  // the field's rounding to Q24.8 rig units / s^2 (half of 2^-8, times h^2:
  // far below an LSB).
  const double lsb = std::ldexp(1.0, -20), bound = (2.0 * with_field.sweeps + 2) * lsb;
  std::printf("base at +4 m/s^2: one-step gap to the oracle %.1f LSB (bound %.0f), to one without the field %.0f LSB\n",
              worst / lsb, bound / lsb, apart / lsb);
  EXPECT_LE(worst, bound);
  EXPECT_GT(apart, 100 * bound) << "the base's acceleration must act on the skin";
}

TEST(SkinDynamicPipeline, BaseAccelerationMustNameAccelerationInputs) {
  sinew::rigc::RigSpec spec;
  sinew::layers::LayerSpecs layers;
  ASSERT_TRUE(sinew::rigc::builtin_rig("arm", sinew::rigc::SkinChoice::kDualQuaternion, &spec));
  ASSERT_TRUE(sinew::layers::builtin_layers("arm", &layers));
  layers.anatomy.skin.solver.dynamic = true;
  layers.anatomy.skin.base_acceleration = {"base.ax", "grip", "base.az"};
  layers.external.push_back({"grip", "N", "force", -40, 40, "spec:3"});
  std::string error;
  EXPECT_EQ(sinew::test::compiled_with_layers(spec, layers, &error), nullptr);
  EXPECT_NE(error.find("base_acceleration input 'grip' is not an acceleration"), std::string::npos) << error;
  layers.external.clear();
  layers.anatomy.skin.base_acceleration = {"base.ax", "base.ay"};
  EXPECT_EQ(sinew::test::compiled_with_layers(spec, layers, &error), nullptr);
  EXPECT_NE(error.find("base_acceleration must name 3 inputs"), std::string::npos) << error;
}

TEST(SkinDynamicPipeline, LoaderRefusesBaseAccelerationInputsThatAreNotAccelerations) {
  std::string error;
  auto moving = arm_on_a_moving_base(&error);
  ASSERT_NE(moving, nullptr) << error;
  const size_t section = sinew::test::section_offset(moving->bytes, sinew::elastic_skin::kSectionElasticSkin);
  ASSERT_NE(section, 0u);
  const size_t field = section + sizeof(pl::LayerSectionHeader) +
                       offsetof(sinew::elastic_skin::SkinSectionParamsV5, base_acceleration_input) + 4;
  const uint32_t force = pl::find_external_input(moving->layers, "elbow.force");
  ASSERT_NE(force, pl::kNoExternalInput);
  const struct {
    uint32_t value;
    const char* expected;
  } cases[] = {
      {99, "SKIN#0.base_acceleration_input[1]: not an external input of the rig (EXTI)"},
      {force, "SKIN#0.base_acceleration_input[1]: names an external input that is not an acceleration"},
  };
  for (const auto& c : cases) {
    sinew::test::LoadedLayers l;
    l.bytes = moving->bytes;
    std::memcpy(l.bytes.data() + field, &c.value, 4);
    sinew::test::fix_crc(&l.bytes);
    std::string refused;
    EXPECT_FALSE(l.load(&refused));
    EXPECT_NE(refused.find(c.expected), std::string::npos) << refused;
  }
}
