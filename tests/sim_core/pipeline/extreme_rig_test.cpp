// Blobs the loader accepts must be safe to run: every field the format
// leaves unchecked (rest scales and translations, inverse-bind linear parts
// at their +-64 limit and translations, DOF inputs) is pushed to its extreme
// on the built-in arm, which then runs the engine (kinematics, LBS and DQS
// skinning). extreme_layers_test.cpp runs every physical layer on the same
// transforms and on layer sections at their limits; the fuzz target runs the
// pipeline on the blobs it makes.
// The sanitizer builds (dev: UBSan, -fno-sanitize-recover) fail on any
// signed overflow or out-of-bounds access; here the outputs must also be
// the same on a second run (no uninitialised reads).
#include <gtest/gtest.h>

#include <climits>

#include "tests/sim_core/pipeline/pipeline_fixture.hpp"

namespace pl = sinew::pipeline;

namespace {

size_t core_section(const std::vector<uint8_t>& bytes, uint32_t id) {
  sinew::rig::FileHeader h;
  std::memcpy(&h, bytes.data(), sizeof(h));
  for (uint32_t i = 0; i < h.section_count; ++i) {
    sinew::rig::SectionEntry e;
    std::memcpy(&e, bytes.data() + h.section_table_offset + i * sizeof(e), sizeof(e));
    if (e.id == id) return e.offset;
  }
  return 0;
}

void put(std::vector<uint8_t>* b, size_t at, int32_t v) { std::memcpy(b->data() + at, &v, 4); }

std::vector<int32_t> run_extremes(sinew::test::LoadedLayers* arm) {
  std::string error;
  pl::PipelineOptions engine_only;
  engine_only.stages = pl::StageSet::none();
  EXPECT_TRUE(arm->start(engine_only, &error)) << error;
  std::vector<int32_t> inputs(arm->pipeline.input_count, 0), out;
  for (int32_t v : {INT32_MAX, INT32_MIN, 0, 0x40000000, -0x40000000}) {
    for (int32_t& in : inputs) in = v;
    pl::pipeline_step(&arm->pipeline, inputs);  // layer errors are allowed; undefined behaviour is not
    for (int a = 0; a < 3; ++a)
      out.insert(out.end(), arm->pipeline.engine.vertices.position[a].begin(),
                 arm->pipeline.engine.vertices.position[a].end());
  }
  return out;
}

}  // namespace

TEST(ExtremeRigs, EveryUncheckedFieldAtItsLimitRunsDefined) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  std::vector<uint8_t> bytes = arm->bytes;
  const size_t joints = core_section(bytes, sinew::rig::kSectionJoints);
  const size_t palette = core_section(bytes, sinew::rig::kSectionPalette);
  ASSERT_NE(joints, 0u);
  ASSERT_NE(palette, 0u);
  for (uint32_t j = 0; j < arm->rig.joint_count(); ++j) {
    const size_t r = joints + j * sizeof(sinew::rig::JointRecord);
    for (size_t c = 0; c < 3; ++c) {
      put(&bytes, r + offsetof(sinew::rig::JointRecord, rest_translation) + 4 * c, c == 1 ? INT32_MIN : INT32_MAX);
      put(&bytes, r + offsetof(sinew::rig::JointRecord, rest_scale) + 4 * c, c == 2 ? INT32_MIN : INT32_MAX);
    }
  }
  for (size_t p = 0; p < arm->rig.palette.size(); ++p) {
    const size_t r =
        palette + p * sizeof(sinew::rig::PaletteRecord) + offsetof(sinew::rig::PaletteRecord, inverse_bind);
    for (size_t k = 0; k < 9; ++k) put(&bytes, r + 4 * k, (k % 2 == 0) ? (1 << 30) : -(1 << 30));  // +-64, the limit
    for (size_t k = 9; k < 12; ++k) put(&bytes, r + 4 * k, k == 10 ? INT32_MIN : INT32_MAX);
  }
  sinew::test::fix_crc(&bytes);
  sinew::test::LoadedLayers extreme;
  extreme.bytes = bytes;
  std::string error;
  ASSERT_TRUE(extreme.load(&error)) << "every field patched is one the format accepts: " << error;
  const std::vector<int32_t> first = run_extremes(&extreme);
  const std::vector<int32_t> second = run_extremes(&extreme);
  EXPECT_EQ(first, second);
}
