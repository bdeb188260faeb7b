// MUSC layer version 4 (layer_format.hpp): a rig whose muscle bellies are
// general superquadrics carries their exponent pairs in a fifth array; the
// writer emits it only then, the loader reads it back, the pipeline runs
// it, and every bad value is refused naming the section, the array, the
// index and the field.
#include <gtest/gtest.h>

#include <cstring>

#include "host_tools/rigc/builtin_rigs.hpp"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"

namespace pl = sinew::pipeline;
namespace muscle = sinew::muscle;
using sinew::test::LoadedLayers;

namespace {

// The built-in arm's layers with a second belly (the first muscle again),
// the first belly's exponents (3, 2.5), the second's the default 4.
std::unique_ptr<LoadedLayers> arm_with_general_belly(std::string* error) {
  sinew::rigc::RigSpec spec;
  sinew::layers::LayerSpecs tables;
  if (!sinew::rigc::builtin_rig("arm", sinew::rigc::SkinChoice::kDualQuaternion, &spec) ||
      !sinew::layers::builtin_layers("arm", &tables))
    return nullptr;
  tables.anatomy.muscles.push_back(tables.anatomy.muscles[0]);
  tables.anatomy.muscles[1].name = "biceps_2";
  tables.anatomy.muscles[0].belly_exponent = 3;
  tables.anatomy.muscles[0].belly_exponent_z = 2.5;
  return sinew::test::compiled_with_layers(spec, tables, error);
}

uint32_t musc_u32(const std::vector<uint8_t>& b, size_t at) {
  uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

// Offset (from the blob start) of element `index` of array `array` of the MUSC section.
size_t musc_element(const std::vector<uint8_t>& b, uint32_t array, uint32_t index) {
  const size_t s = sinew::test::section_offset(b, sinew::muscle::kSectionMuscles);
  const uint32_t params = musc_u32(b, s + 4);
  const size_t entry = s + sizeof(pl::LayerSectionHeader) + ((params + 7u) & ~7u) + array * sizeof(pl::LayerArrayEntry);
  return s + musc_u32(b, entry) + index * musc_u32(b, entry + 8);
}

std::string musc_load_error(std::vector<uint8_t> bytes) {
  sinew::test::fix_crc(&bytes);
  LoadedLayers l;
  l.bytes = std::move(bytes);
  std::string error;
  return l.load(&error) ? std::string() : error;
}

}  // namespace

TEST(MuscleExponents, GeneralBelliesCompileToMuscVersion4AndRun) {
  std::string error;
  auto l = arm_with_general_belly(&error);
  ASSERT_NE(l, nullptr) << error;
  const size_t section = sinew::test::section_offset(l->bytes, sinew::muscle::kSectionMuscles);
  EXPECT_EQ(musc_u32(l->bytes, section), sinew::muscle::kMusclesSectionVersion4);
  const muscle::MuscleModel& m = l->layers.anatomy.muscles;
  ASSERT_EQ(m.primitives.size(), 2u);
  ASSERT_EQ(m.exponents.size(), 2u);
  EXPECT_EQ(m.exponents[0].power_xy, 3 << 16);
  EXPECT_EQ(m.exponents[0].power_z, 5 << 15);
  EXPECT_EQ(m.primitives[0].exponent, 0) << "a general pair: the record's exponent is 0";
  EXPECT_EQ(m.exponents[1].power_xy, 4 << 16);
  EXPECT_EQ(m.exponents[1].power_z, 4 << 16);
  EXPECT_EQ(m.primitives[1].exponent, 4) << "an equal 4 keeps the exact kernel";
  EXPECT_TRUE(m.deformations.empty());
  // The spec's default end axes, from the bones' normals (§4.2), travel in
  // the shapes array, one per muscle.
  EXPECT_EQ(m.shapes.size(), m.muscles.size());
  // The built-in arm (exponent 4 only) keeps its older section and bytes.
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  EXPECT_LT(musc_u32(arm->bytes, sinew::test::section_offset(arm->bytes, sinew::muscle::kSectionMuscles)),
            sinew::muscle::kMusclesSectionVersion4);
  EXPECT_TRUE(arm->layers.anatomy.muscles.exponents.empty());
  // The pipeline steps it; the muscle step hands the pair to the frame.
  ASSERT_TRUE(l->start(pl::PipelineOptions{}, &error)) << error;
  std::vector<int32_t> inputs(l->pipeline.input_count, 0);
  for (int k = 0; k < 20; ++k) {
    inputs[0] = sinew::test::degrees(k * 6.0);
    const pl::PipelineStatus st = pl::pipeline_step(&l->pipeline, inputs);
    ASSERT_TRUE(st.ok()) << st.message;
  }
}

TEST(MuscleExponents, BadValuesAreRefusedNamingSectionArrayIndexAndField) {
  std::string error;
  auto l = arm_with_general_belly(&error);
  ASSERT_NE(l, nullptr) << error;
  const std::vector<uint8_t>& good = l->bytes;
  struct Case {
    const char* name;
    uint32_t array, index, offset, value;  // a u32 (or, with offset 2, the record's exponent byte)
    const char* expected;
  };
  const Case cases[] = {
      {"power_xy below 1", 4, 0, 0, 0xFFFFu, "MUSC#0: exponents[0].power_xy: outside [1, 16]"},
      {"power_z above 16", 4, 1, 4, (16u << 16) + 1, "MUSC#0: exponents[1].power_z: outside [1, 16]"},
      {"negative power", 4, 0, 4, 0x80000000u, "MUSC#0: exponents[0].power_z: outside [1, 16]"},
      {"record exponent of a general pair", 1, 0, 2, 4, "MUSC#0: primitive[0].exponent: must be the exponents pair's"},
      {"record exponent of an exact pair", 1, 1, 2, 0, "MUSC#0: primitive[1].exponent: must be the exponents pair's"},
      {"sphere not 2", 1, 0, 0, 0, "MUSC#0: exponents[0].power_xy: must be exactly 2"},
      {"cylinder not 2", 1, 1, 0, 1, "MUSC#0: exponents[1].power_xy: must be exactly 2"},
  };
  for (const Case& c : cases) {
    std::vector<uint8_t> bytes = good;
    const size_t at = musc_element(bytes, c.array, c.index) + c.offset;
    if (c.array == 1) {
      bytes[at] = static_cast<uint8_t>(c.value);  // kind (offset 0) or exponent (offset 2): bytes
    } else {
      std::memcpy(bytes.data() + at, &c.value, 4);
    }
    const std::string got = musc_load_error(bytes);
    EXPECT_NE(got.find(c.expected), std::string::npos) << c.name << ": got '" << got << "'";
  }
  // One pair for two primitives.
  std::vector<uint8_t> bytes = good;
  const size_t s = sinew::test::section_offset(bytes, sinew::muscle::kSectionMuscles);
  const size_t entry = s + sizeof(pl::LayerSectionHeader) + sizeof(sinew::muscle::MusclesSectionParams) +
                       4 * sizeof(pl::LayerArrayEntry);  // the params (8 bytes) need no padding
  const uint32_t one = 1;
  std::memcpy(bytes.data() + entry + 4, &one, 4);
  EXPECT_NE(musc_load_error(bytes).find("MUSC#0: muscle model.exponents: must be empty or one per primitive"),
            std::string::npos)
      << musc_load_error(bytes);
  // A version this loader does not know.
  bytes = good;
  const uint32_t five = 5;
  std::memcpy(bytes.data() + s, &five, 4);
  EXPECT_NE(musc_load_error(bytes).find("MUSC#0.layer_version: unsupported layer section version"), std::string::npos);
  // The unmodified blob loads.
  EXPECT_EQ(musc_load_error(good), "");
}
