// Golden determinism of the pipeline with every layer on: the built-in arm's
// blob with its layer sections, and every step's outputs (skinned and
// layered vertices, the SPH bend and yield), must hash to the committed
// values on every build (x86_64, aarch64, armhf; gcc and clang).
#include <gtest/gtest.h>

#include <cmath>

#include "host_tools/determinism/output_hash.hpp"
#include "tests/sim_core/pipeline/golden.hpp"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"

namespace det = sinew::determinism;
namespace pl = sinew::pipeline;

TEST(PipelineDeterminism, EveryLayerOnTheArmMatchesGolden) {
  std::string error;
  auto arm = sinew::test::builtin_with_layers("arm", &error);
  ASSERT_NE(arm, nullptr) << error;
  det::OutputHash blob;
  for (uint8_t b : arm->bytes) blob.add_u32(b);
  const uint64_t blob_hash = blob.digest();
  ASSERT_TRUE(arm->start({}, &error)) << error;
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0);
  det::OutputHash out;
  constexpr int kSteps = 12;
  for (int s = 0; s < kSteps; ++s) {
    inputs[0] = sinew::test::degrees(40.0 * std::sin(s * 0.3));
    inputs[3] = sinew::test::degrees(70.0 + 60.0 * std::sin(s * 0.5));
    inputs[4] = sinew::test::degrees(30.0 * std::sin(s * 0.7));
    inputs[arm->rig.input_count] = static_cast<int32_t>(30 * 65536 * std::sin(s * 0.4));
    const pl::PipelineStatus st = pl::pipeline_step(&arm->pipeline, inputs);
    ASSERT_TRUE(st.ok()) << st.message;
    for (int a = 0; a < 3; ++a)
      for (int32_t v : arm->pipeline.engine.vertices.position[a]) out.add_i32(v);
    out.add_u32(static_cast<uint32_t>(arm->pipeline.sph.joint[0].bend));
    out.add_u32(arm->pipeline.sph.joint[0].yielded_particles);
    out.add_u32(arm->pipeline.saturated);
  }
  const uint64_t output_hash = out.digest();
  det::print_determinism_line("arm-layers-blob", blob_hash);
  det::print_determinism_line("pipeline-arm-all-layers", output_hash);
  EXPECT_EQ(blob_hash, sinew::test::golden::kArmLayersBlob) << "the built-in arm's compiled layers changed";
  EXPECT_EQ(output_hash, sinew::test::golden::kPipelineArmAllLayers) << "the pipeline's outputs changed";
}
