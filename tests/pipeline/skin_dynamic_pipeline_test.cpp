// The dynamic elastic skin through rigc and the board's loader: a [skin]
// mode = "dynamic" rig writes a version 2 SKIN section, loads with its
// solver record, and steps in the pipeline at the loop's rate; a static
// rig keeps its version 1 section.
#include <gtest/gtest.h>

#include "host_tools/layers/rig_layers.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "tests/pipeline/pipeline_fixture.hpp"

namespace pl = sinew::pipeline;

namespace {

std::unique_ptr<sinew::test::LoadedLayers> arm_with_dynamic_skin(std::string* error) {
  sinew::rigc::RigSpec spec;
  sinew::layers::LayerSpecs layers;
  if (!sinew::rigc::builtin_rig("arm", sinew::rigc::SkinChoice::kDualQuaternion, &spec) ||
      !sinew::layers::builtin_layers("arm", &layers))
    return nullptr;
  layers.skin.solver.dynamic = true;
  layers.skin.solver.gravity[1] = -9.81;
  return sinew::test::compiled_with_layers(std::move(spec), layers, error);
}

uint32_t skin_section_version(const std::vector<uint8_t>& bytes) {
  const size_t at = sinew::test::section_offset(bytes, pl::kSectionElasticSkin);
  uint32_t v = 0;
  if (at != 0) std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

}  // namespace

TEST(SkinDynamicPipeline, StaticRigKeepsVersion1) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  EXPECT_EQ(skin_section_version(arm->bytes), 1u);
  EXPECT_EQ(arm->layers.skin.solver.mode, static_cast<uint8_t>(sinew::elastic_skin::SkinMode::kStatic));
}

TEST(SkinDynamicPipeline, DynamicRigLoadsAndStepsAtTheLoopRate) {
  std::string error;
  auto arm = arm_with_dynamic_skin(&error);
  ASSERT_NE(arm, nullptr) << error;
  EXPECT_EQ(skin_section_version(arm->bytes), pl::kSkinSectionVersion2);
  const sinew::elastic_skin::SkinSolverParams& solver = arm->layers.skin.solver;
  EXPECT_EQ(solver.mode, static_cast<uint8_t>(sinew::elastic_skin::SkinMode::kDynamic));
  EXPECT_LT(solver.gravity.y, 0);
  pl::PipelineOptions options;
  options.tick_hz = 500;
  ASSERT_TRUE(arm->start(options, &error)) << error;
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0);
  // 100 ticks (0.2 s; 2 substeps of the whole arm skin each, slow under
  // ASan and qemu): the first DOF turns 90 degrees in 0.1 s, then stops.
  for (int k = 0; k < 100; ++k) {
    inputs[0] = sinew::test::degrees(k < 50 ? k * 1.8 : 90.0);
    const pl::PipelineStatus st = pl::pipeline_step(&arm->pipeline, inputs);
    ASSERT_TRUE(st.ok()) << st.message;
    ASSERT_EQ(arm->pipeline.skin.stats.substeps, 2u);  // ceil(1000 / 500): the default substep_hz
    ASSERT_EQ(arm->pipeline.skin.stats.inside_after, 0u) << "tick " << k;
  }
}
