// The C API (sim_core/capi/sinew.h): the built-in arm with every layer,
// stepped through it, gives the pipeline's words step for step; bad
// memory, a corrupt blob and too few inputs are refused with a message.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "sim_core/capi/sinew.h"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"

namespace capi_test {

// 8-byte aligned blocks of at least `bytes`.
struct Block {
  std::vector<uint64_t> words;
  void* get(size_t bytes) {
    words.assign(bytes / 8 + 1, 0);
    return words.data();
  }
};

struct Loaded {
  Block blob, rig_memory, layer_memory, pipeline_memory;
  size_t blob_bytes = 0;
  sinew_rig* rig = nullptr;
  sinew_pipeline* pipeline = nullptr;
};

// The built-in arm's compiled blob, loaded and started through the C API.
bool load_arm(Loaded* l, std::string* error) {
  auto arm = sinew::test::builtin_with_layers("arm", error);
  if (arm == nullptr) return false;
  l->blob_bytes = arm->bytes.size();
  void* blob = l->blob.get(l->blob_bytes);
  std::memcpy(blob, arm->bytes.data(), l->blob_bytes);
  size_t bytes = 0;
  sinew_status s = sinew_rig_bytes(blob, l->blob_bytes, &bytes);
  if (s.code == SINEW_OK) s = sinew_rig_load(blob, l->blob_bytes, l->rig_memory.get(bytes), bytes, &l->rig);
  if (s.code == SINEW_OK) s = sinew_layers_bytes(l->rig, blob, l->blob_bytes, &bytes);
  if (s.code == SINEW_OK) s = sinew_layers_load(l->rig, blob, l->blob_bytes, l->layer_memory.get(bytes), bytes);
  if (s.code == SINEW_OK) {
    bytes = sinew_pipeline_state_bytes(l->rig, nullptr);
    s = sinew_pipeline_init(l->rig, nullptr, l->pipeline_memory.get(bytes), bytes, &l->pipeline);
  }
  if (s.code != SINEW_OK) *error = s.message;
  return s.code == SINEW_OK;
}

}  // namespace capi_test

// Step for step, the C API's vertices are the C++ pipeline's, word for word
// (the C++ pipeline's own outputs are golden-tested in
// PipelineDeterminism), with every layer of the built-in arm on.
TEST(CApi, ArmWithEveryLayerStepsAsThePipeline) {
  capi_test::Loaded l;
  std::string error;
  ASSERT_TRUE(capi_test::load_arm(&l, &error)) << error;
  auto arm = sinew::test::builtin_with_layers("arm", &error);
  ASSERT_NE(arm, nullptr) << error;
  ASSERT_TRUE(arm->start({}, &error)) << error;
  const sinew_rig_info info = sinew_rig_get_info(l.rig);
  EXPECT_EQ(info.joint_count, arm->rig.joint_count());
  EXPECT_EQ(info.vertex_count, arm->rig.vertex_count());
  EXPECT_EQ(info.layer_count, 4u);  // sph, metaballs, barnet, anatomy
  ASSERT_EQ(sinew_stage_count(), 5u);
  EXPECT_STREQ(sinew_stage_name(0), "skinning");
  EXPECT_EQ(sinew_stage_name(5), nullptr);
  ASSERT_EQ(info.input_count + info.external_input_count, arm->pipeline.input_count);
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0);
  bool moved = false;
  for (int s = 0; s < 12; ++s) {
    inputs[0] = sinew::test::degrees(40.0 * std::sin(s * 0.3));
    inputs[3] = sinew::test::degrees(70.0 + 60.0 * std::sin(s * 0.5));
    inputs[4] = sinew::test::degrees(30.0 * std::sin(s * 0.7));
    inputs[info.input_count] = static_cast<int32_t>(30 * 65536 * std::sin(s * 0.4));
    const sinew_status st = sinew_pipeline_step(l.pipeline, inputs.data(), inputs.size());
    ASSERT_EQ(st.code, SINEW_OK) << st.message;
    ASSERT_TRUE(sinew::pipeline::pipeline_step(&arm->pipeline, inputs).ok());
    const sinew_vertices v = sinew_pipeline_vertices(l.pipeline);
    ASSERT_EQ(v.count, info.vertex_count);
    const int32_t* axes[3] = {v.x, v.y, v.z};
    for (int a = 0; a < 3; ++a) {
      const auto& expected = arm->pipeline.engine.vertices.position[a];
      ASSERT_EQ(std::memcmp(axes[a], expected.data(), expected.size() * sizeof(int32_t)), 0)
          << "step " << s << ", axis " << a;
      moved = moved || std::memcmp(axes[a], arm->rig.position[a].data(), expected.size() * sizeof(int32_t)) != 0;
    }
  }
  EXPECT_TRUE(moved) << "the skin never left its rest pose";
}

TEST(CApi, RefusesBadMemoryCorruptBlobsAndShortInputs) {
  capi_test::Loaded l;
  std::string error;
  ASSERT_TRUE(capi_test::load_arm(&l, &error)) << error;
  const void* blob = l.blob.words.data();
  size_t bytes = 0;
  ASSERT_EQ(sinew_rig_bytes(blob, l.blob_bytes, &bytes).code, SINEW_OK);
  capi_test::Block small;
  sinew_rig* rig = nullptr;
  sinew_status s = sinew_rig_load(blob, l.blob_bytes, small.get(bytes), bytes - 8, &rig);
  EXPECT_EQ(s.code, SINEW_ERROR_ARGUMENT);
  EXPECT_NE(std::string(s.message).find("smaller"), std::string::npos) << s.message;
  s = sinew_rig_load(blob, l.blob_bytes, static_cast<uint8_t*>(small.get(bytes + 8)) + 4, bytes, &rig);
  EXPECT_EQ(s.code, SINEW_ERROR_ARGUMENT);
  EXPECT_NE(std::string(s.message).find("aligned"), std::string::npos) << s.message;
  EXPECT_EQ(rig, nullptr);
  // A corrupt blob: one byte of the skin flipped (the checksum refuses it).
  capi_test::Block corrupt;
  auto* bad = static_cast<uint8_t*>(corrupt.get(l.blob_bytes));
  std::memcpy(bad, blob, l.blob_bytes);
  bad[l.blob_bytes / 2] ^= 0x5A;
  size_t rig_bytes = 0;
  s = sinew_rig_bytes(bad, l.blob_bytes, &rig_bytes);
  if (s.code == SINEW_OK) {
    s = sinew_rig_load(bad, l.blob_bytes, small.get(rig_bytes), rig_bytes, &rig);
    if (s.code == SINEW_OK) s = sinew_layers_bytes(rig, bad, l.blob_bytes, &rig_bytes);
  }
  EXPECT_EQ(s.code, SINEW_ERROR_BLOB);
  EXPECT_GT(std::strlen(s.message), 0u);
  // Too few inputs: refused, the pose kept.
  const sinew_rig_info info = sinew_rig_get_info(l.rig);
  std::vector<int32_t> inputs(info.input_count + info.external_input_count, 0);
  const int32_t x0 = sinew_pipeline_vertices(l.pipeline).x[0];
  s = sinew_pipeline_step(l.pipeline, inputs.data(), info.input_count - 1);
  EXPECT_EQ(s.code, SINEW_ERROR_STEP);
  EXPECT_NE(std::string(s.message).find("fewer inputs"), std::string::npos) << s.message;
  EXPECT_EQ(sinew_pipeline_vertices(l.pipeline).x[0], x0);
  EXPECT_EQ(sinew_pipeline_step(nullptr, inputs.data(), inputs.size()).code, SINEW_ERROR_ARGUMENT);
}
