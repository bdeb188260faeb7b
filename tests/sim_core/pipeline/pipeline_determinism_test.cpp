// Golden determinism of the pipeline with every layer on: the built-in arm's
// blob with its layer sections, and every step's outputs (skinned and
// layered vertices, the SPH bend and yield), must hash to the committed
// values on every build (x86_64, aarch64, armhf; gcc and clang).
#include <gtest/gtest.h>

#include <cmath>

#include "host_tools/determinism/output_hash.hpp"
#include "tests/sim_core/pipeline/golden.hpp"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"
#include "tests/support/test_workers.hpp"

namespace det = sinew::determinism;
namespace pl = sinew::pipeline;

namespace pipeline_determinism_test {

struct Hashes {
  uint64_t blob = 0, output = 0;
  uint32_t parallel_loops = 0;  // loops the workers ran (0 without workers)
};

// The arm with every layer, 12 steps of a fixed motion; workers: null or
// the test pool with that many parts.
Hashes run_arm(uint32_t workers, std::string* error) {
  Hashes h;
  auto arm = sinew::test::builtin_with_layers("arm", error);
  if (arm == nullptr) return h;
  det::OutputHash blob;
  for (uint8_t b : arm->bytes) blob.add_u32(b);
  h.blob = blob.digest();
  sinew::test::ThreadPerRangeWorkers pool(workers == 0 ? 1 : workers);
  pl::PipelineOptions options;
  if (workers != 0) options.workers = pool.workers();
  if (!arm->start(options, error)) return h;
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0);
  det::OutputHash out;
  constexpr int kSteps = 12;
  for (int s = 0; s < kSteps; ++s) {
    inputs[0] = sinew::test::degrees(40.0 * std::sin(s * 0.3));
    inputs[3] = sinew::test::degrees(70.0 + 60.0 * std::sin(s * 0.5));
    inputs[4] = sinew::test::degrees(30.0 * std::sin(s * 0.7));
    inputs[arm->rig.input_count] = static_cast<int32_t>(30 * 65536 * std::sin(s * 0.4));
    const pl::PipelineStatus st = pl::pipeline_step(&arm->pipeline, inputs);
    if (!st.ok()) {
      *error = st.message;
      return h;
    }
    for (int a = 0; a < 3; ++a)
      for (int32_t v : arm->pipeline.engine.vertices.position[a]) out.add_i32(v);
    out.add_u32(static_cast<uint32_t>(arm->pipeline.sph.joint[0].bend));
    out.add_u32(arm->pipeline.sph.joint[0].yielded_particles);
    out.add_u32(arm->pipeline.saturated);
  }
  h.output = out.digest();
  h.parallel_loops = workers == 0 ? 0 : pool.loops();
  return h;
}

}  // namespace pipeline_determinism_test

TEST(PipelineDeterminism, EveryLayerOnTheArmMatchesGolden) {
  std::string error;
  const pipeline_determinism_test::Hashes h = pipeline_determinism_test::run_arm(0, &error);
  ASSERT_TRUE(error.empty()) << error;
  det::print_determinism_line("arm-layers-blob", h.blob);
  det::print_determinism_line("pipeline-arm-all-layers", h.output);
  EXPECT_EQ(h.blob, sinew::test::golden::kArmLayersBlob) << "the built-in arm's compiled layers changed";
  EXPECT_EQ(h.output, sinew::test::golden::kPipelineArmAllLayers) << "the pipeline's outputs changed";
}

// PipelineOptions::workers changes no output word: every worker count, with
// the ranges run in reverse on their own threads, gives the golden hash.
// The parallel loops must have run (a stage that ignored its workers would
// pass the hash trivially).
TEST(PipelineDeterminism, EveryWorkerCountMatchesGolden) {
  for (const uint32_t workers : {1u, 2u, 3u, 4u, 7u}) {
    std::string error;
    const pipeline_determinism_test::Hashes h = pipeline_determinism_test::run_arm(workers, &error);
    ASSERT_TRUE(error.empty()) << workers << " workers: " << error;
    EXPECT_EQ(h.output, sinew::test::golden::kPipelineArmAllLayers) << workers << " workers";
    if (workers > 1) {
      EXPECT_GT(h.parallel_loops, 0u) << workers << " workers: no loop ran over the workers";
    }
  }
}
