// The dynamic elastic skin on a real glTF model, compiled from its spec by
// rigc's library and run through the board's loader and pipeline.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "host_tools/rigc/toml_spec.hpp"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"
#include "tests/support/alloc_guard.hpp"

namespace pl = sinew::pipeline;

// The dynamic skin on a real glTF model (tests/data/generic_hand_dynamic_
// layers.toml): compiled with its tissue defaults, run at 100 Hz through a
// sweep of every input (the base's acceleration included): every tick
// steps, no fat point is left inside a primitive, and no tick allocates.
TEST(DynamicSkinGltf, RunsOnTheHandWithoutAllocating) {
  sinew::rigc::RigSpec spec;
  sinew::layers::LayerSpecs layers;
  std::string error;
  ASSERT_TRUE(sinew::rigc::load_toml_rig(std::string(SINEW_SOURCE_DIR) + "/tests/data/generic_hand_dynamic_layers.toml",
                                         &spec, &layers, &error))
      << error;
  auto hand = sinew::test::compiled_with_layers(std::move(spec), layers, &error);
  ASSERT_NE(hand, nullptr) << error;
  ASSERT_EQ(hand->layers.anatomy.skin.solver.mode, static_cast<uint8_t>(sinew::elastic_skin::SkinMode::kDynamic));
  pl::PipelineOptions options;
  options.tick_hz = 100;
  ASSERT_TRUE(hand->start(options, &error)) << error;
  std::vector<int32_t> inputs(hand->pipeline.input_count, 0);
  const auto sweep = [&](int k) {
    for (size_t i = 0; i < inputs.size(); ++i)
      inputs[i] = static_cast<int32_t>(std::lround(0x10000000 * std::sin(0.05 * k + 0.7 * static_cast<double>(i))));
  };
  sweep(0);
  ASSERT_TRUE(pl::pipeline_step(&hand->pipeline, inputs).ok());  // the first step settles the skin
  sinew::test::AllocationCounter allocations;
  for (int k = 1; k <= 300; ++k) {
    sweep(k);
    const pl::PipelineStatus st = pl::pipeline_step(&hand->pipeline, inputs);
    ASSERT_TRUE(st.ok()) << st.message;
    ASSERT_EQ(hand->pipeline.anatomy.skin.stats.inside_after, 0u) << "tick " << k;
  }
  EXPECT_EQ(allocations.allocations(), 0u);
  std::printf("glTF hand, dynamic skin at 100 Hz: %u substeps a tick, omega_max %u rad/s\n",
              hand->pipeline.anatomy.skin.stats.substeps, hand->pipeline.anatomy.skin.stats.omega_max);
}
