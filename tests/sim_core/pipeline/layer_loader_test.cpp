// The layer sections of a rig blob (sim_core/pipeline/layer_format.hpp):
// what the built-in arm carries, and every class of corruption refused with
// a message naming the section, its instance and the field.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <random>

#include "host_tools/rigc/builtin_rigs.hpp"
#include "host_tools/rigc/rig_spec.hpp"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"
#include "tests/support/soak.hpp"

namespace pl = sinew::pipeline;
using sinew::test::LoadedLayers;

namespace {

void put_u32(std::vector<uint8_t>* b, size_t at, uint32_t v) { std::memcpy(b->data() + at, &v, 4); }
uint32_t get_u32(const std::vector<uint8_t>& b, size_t at) {
  uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

// Where array `i` of a layer section's array table is.
size_t array_entry(const std::vector<uint8_t>& b, size_t section, uint32_t i) {
  const uint32_t params = get_u32(b, section + 4);
  return section + sizeof(pl::LayerSectionHeader) + ((params + 7u) & ~7u) + i * sizeof(pl::LayerArrayEntry);
}

struct Corruption {
  const char* name;
  uint32_t section;
  // Returns the byte offset to overwrite (from the blob start) and the value.
  std::function<void(std::vector<uint8_t>*, size_t)> apply;
  const char* expected;  // in the loader's message
};

std::string load_error(const std::vector<uint8_t>& bytes) {
  LoadedLayers l;
  l.bytes = bytes;
  std::string error;
  return l.load(&error) ? std::string() : error;
}

}  // namespace

TEST(LayerLoader, BuiltInArmCarriesEveryLayerKind) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  const pl::LayerSet& l = arm->layers;
  EXPECT_EQ(l.sph.count, 1u);
  EXPECT_TRUE(l.metaballs.present);
  EXPECT_TRUE(l.anatomy.has_muscles);
  EXPECT_TRUE(l.anatomy.has_skin);
  EXPECT_EQ(l.barnet.count, 1u);
  ASSERT_EQ(l.external_count(), 1u);
  EXPECT_STREQ(l.external[0].name, "elbow.force");
  EXPECT_STREQ(l.external[0].unit, "N");
  EXPECT_EQ(l.rate_hz, 1000u);
  EXPECT_EQ(l.sph.joint[0].force_input, 0u);
  EXPECT_EQ(pl::find_external_input(l, "elbow.force"), 0u);
  EXPECT_EQ(pl::find_external_input(l, "wrist.force"), pl::kNoExternalInput);
  sinew::rig::FileHeader h;
  std::memcpy(&h, arm->bytes.data(), sizeof(h));
  EXPECT_EQ(h.version_minor, 1u) << "layer sections are format 1.1";
}

// A 1.0 loader skips unknown sections: the core of a 1.1 blob loads alone.
TEST(LayerLoader, TheCoreLoaderSkipsLayerSections) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  size_t bytes = 0;
  EXPECT_TRUE(sinew::rig::rig_validate(arm->data(), arm->bytes.size(), &bytes).ok());
  EXPECT_LT(bytes, arm->bytes.size() / 2) << "the core arena holds no layer data";
}

TEST(LayerLoader, CorruptionsAreRefusedNamingSectionAndField) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  const auto at = [](uint32_t offset, uint32_t value) {
    return [=](std::vector<uint8_t>* b, size_t s) { put_u32(b, s + offset, value); };
  };
  const auto array_field = [](uint32_t i, uint32_t field, uint32_t value, bool add = false) {
    return [=](std::vector<uint8_t>* b, size_t s) {
      const size_t e = array_entry(*b, s, i) + field;
      put_u32(b, e, add ? get_u32(*b, e) + value : value);
    };
  };
  const Corruption cases[] = {
      {"version", sinew::sph::kSectionSphJoint, at(0, 3), "SPHJ#0.layer_version: unsupported layer section version"},
      {"params size", sinew::sph::kSectionSphJoint, at(4, 80), "SPHJ#0.params_size: does not match"},
      {"array count", sinew::sph::kSectionSphJoint, at(8, 10), "SPHJ#0.array_count: does not match"},
      {"rate", sinew::sph::kSectionSphJoint, at(12, 0), "SPHJ#0.rate_hz: an SPH joint's gains need its tick rate"},
      {"element size", sinew::sph::kSectionSphJoint, array_field(0, 8, 8), "SPHJ#0.rest_local_x: element size"},
      {"count beyond maximum", sinew::sph::kSectionSphJoint, array_field(0, 4, 9000),
       "SPHJ#0.rest_local_x: count exceeds the documented maximum"},
      {"misaligned array", sinew::sph::kSectionSphJoint, array_field(7, 0, 4, true),
       "SPHJ#0.skin_vertex: outside the section or misaligned"},
      {"array past the section", sinew::sph::kSectionSphJoint, array_field(0, 0, 0x7FFFFFF8u),
       "SPHJ#0.rest_local_x: outside the section or misaligned"},
      {"count past the section", sinew::sph::kSectionSphJoint, array_field(10, 4, 8000),
       "SPHJ#0.skin_rest_z: outside the section"},
      {"joint index", sinew::sph::kSectionSphJoint, at(32 + 48, 99), "SPHJ#0: "},
      {"force input", sinew::sph::kSectionSphJoint, at(32 + 76, 5), "SPHJ#0.force_input: names no external input"},
      {"gain", sinew::sph::kSectionSphJoint, at(32 + 12, 0x7FFFFFFFu), "SPHJ#0: "},
      {"input name", pl::kSectionExternalInputs,
       [](std::vector<uint8_t>* b, size_t s) {
         const size_t data = get_u32(*b, array_entry(*b, s, 0));
         std::memset(b->data() + s + data, 'A', sinew::rig::kNameBytes);
       },
       "EXTI#0.name[0]: empty or not NUL-terminated"},
      {"input range", pl::kSectionExternalInputs,
       [](std::vector<uint8_t>* b, size_t s) { put_u32(b, s + get_u32(*b, array_entry(*b, s, 0)) + 52, 0x7FFFFFFF); },
       "EXTI#0.min[0]: must be below max"},
      {"input quantity", pl::kSectionExternalInputs,
       [](std::vector<uint8_t>* b, size_t s) { put_u32(b, s + get_u32(*b, array_entry(*b, s, 0)) + 48, 9); },
       "EXTI#0.quantity[0]: unknown quantity"},
      {"metaballs vertices", sinew::metaballs::kSectionMetaballs, at(36, 7),
       "MBAL#0: vertex_count: differs from the rig's"},
      {"metaballs model", sinew::metaballs::kSectionMetaballs, at(40, 99), "MBAL#0: "},
      {"ring vertices", sinew::muscle::kSectionMuscles, at(36, 6), "MUSC#0: "},
      {"skin vertices", sinew::elastic_skin::kSectionElasticSkin, at(36, 9),
       "SKIN#0.vertex_count: differs from the rig's"},
      {"skin iterations", sinew::elastic_skin::kSectionElasticSkin, at(40, 0), "SKIN#0: "},
      {"skin region", sinew::elastic_skin::kSectionElasticSkin,
       [](std::vector<uint8_t>* b, size_t s) { put_u32(b, s + get_u32(*b, array_entry(*b, s, 5)), 99999); },
       "SKIN#0.region_vertex[0]: not an ascending vertex index of the rig"},
      {"skin region weight", sinew::elastic_skin::kSectionElasticSkin,
       [](std::vector<uint8_t>* b, size_t s) { put_u32(b, s + get_u32(*b, array_entry(*b, s, 6)), 0); },
       "SKIN#0.region_weight[0]: outside (0, 1]"},
      {"bar-net joints", sinew::barnet::kSectionBarnet, at(32, 3), "BNET#0: joint_count: differs from the rig's"},
      {"bar-net model", sinew::barnet::kSectionBarnet,
       [](std::vector<uint8_t>* b, size_t s) { put_u32(b, s + get_u32(*b, array_entry(*b, s, 2)), 9999); }, "BNET#0: "},
  };
  for (const Corruption& c : cases) {
    std::vector<uint8_t> bytes = arm->bytes;
    const size_t section = sinew::test::section_offset(bytes, c.section);
    ASSERT_NE(section, 0u) << c.name;
    c.apply(&bytes, section);
    sinew::test::fix_crc(&bytes);
    const std::string error = load_error(bytes);
    EXPECT_NE(error.find(c.expected), std::string::npos) << c.name << ": got '" << error << "'";
  }
}

// Section-table level: a second metaballs section, a skin without muscles.
TEST(LayerLoader, InstanceLimitsAndDependenciesAreEnforced) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  const auto retag = [&](uint32_t from, uint32_t to) {
    std::vector<uint8_t> bytes = arm->bytes;
    sinew::rig::FileHeader h;
    std::memcpy(&h, bytes.data(), sizeof(h));
    for (uint32_t i = 0; i < h.section_count; ++i) {
      const size_t at = h.section_table_offset + i * sizeof(sinew::rig::SectionEntry);
      if (get_u32(bytes, at) == from) put_u32(&bytes, at, to);
    }
    sinew::test::fix_crc(&bytes);
    return load_error(bytes);
  };
  EXPECT_NE(retag(sinew::barnet::kSectionBarnet, sinew::metaballs::kSectionMetaballs)
                .find("MBAL#1: more instances than the format allows"),
            std::string::npos);
  EXPECT_NE(
      retag(sinew::muscle::kSectionMuscles, 0x58585858u).find("SKIN#0: needs a MUSC section, which the blob lacks"),
      std::string::npos);
}

TEST(LayerLoader, ArenaTooSmallIsRefused) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  size_t bytes = 0;
  ASSERT_TRUE(pl::layers_validate(arm->rig, arm->data(), arm->bytes.size(), &bytes).ok());
  std::vector<uint64_t> small(bytes / 16);
  pl::LayerSet set;
  const sinew::rig::LoadStatus st =
      pl::layers_init(arm->rig, arm->data(), arm->bytes.size(), small.data(), small.size() * 8, &set);
  EXPECT_EQ(st.error, sinew::rig::LoadError::kArenaTooSmall);
}

// Random byte changes anywhere in the layer sections (CRC fixed up): every
// result is a clean refusal or a model that passed every validator; the
// sanitizer builds check nothing is read out of bounds.
TEST(LayerLoader, RandomCorruptionNeverCrashes) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  const size_t first = sinew::test::section_offset(arm->bytes, pl::kSectionExternalInputs);
  ASSERT_NE(first, 0u);
  std::mt19937_64 rng(0x5eed);
  const int trials = sinew::test::emulated() ? 40 : 120;
  int refused = 0;
  for (int t = 0; t < trials; ++t) {
    std::vector<uint8_t> bytes = arm->bytes;
    for (int k = 0; k < 4; ++k) {
      const size_t at = first + static_cast<size_t>(rng() % (bytes.size() - first));
      bytes[at] = static_cast<uint8_t>(rng());
    }
    sinew::test::fix_crc(&bytes);
    refused += load_error(bytes).empty() ? 0 : 1;
  }
  std::printf("random layer corruption: %d of %d refused, the rest valid\n", refused, trials);
  SUCCEED();
}

// SPHJ versions (layer_format.hpp): the built-in arm has no surface tension,
// so its section stays version 1 and loads with tension_gain 0; the same
// section rewritten as version 2 loads every field as before plus the gain.
TEST(LayerLoader, SphVersion2CarriesTheSurfaceTension) {
  auto arm = sinew::test::arm_with_layers();
  ASSERT_NE(arm, nullptr);
  const size_t section = sinew::test::section_offset(arm->bytes, sinew::sph::kSectionSphJoint);
  ASSERT_NE(section, 0u);
  EXPECT_EQ(get_u32(arm->bytes, section), 1u) << "no tension: the writer keeps version 1";
  const sinew::sph::SphParams v1 = arm->layers.sph.joint[0].model.params;
  EXPECT_EQ(v1.tension_gain, 0);
  const size_t params = section + sizeof(pl::LayerSectionHeader);
  sinew::sph::SphSectionParamsV1 old;
  std::memcpy(&old, arm->bytes.data() + params, sizeof old);
  sinew::sph::SphSectionParams now{};
  std::memcpy(static_cast<void*>(&now.params), old.params, sizeof old.params);
  now.params.tension_gain = 12345;
  now.joint = old.joint;
  now.force_input = old.force_input;
  LoadedLayers l;
  l.bytes = arm->bytes;
  std::memcpy(l.bytes.data() + params, &now, sizeof now);
  put_u32(&l.bytes, section, sinew::sph::kSphSectionVersion2);
  sinew::test::fix_crc(&l.bytes);
  std::string error;
  ASSERT_TRUE(l.load(&error)) << error;
  const sinew::sph::SphModel& m = l.layers.sph.joint[0].model;
  EXPECT_EQ(m.params.tension_gain, 12345);
  sinew::sph::SphParams expected = v1;
  expected.tension_gain = 12345;
  EXPECT_EQ(0, std::memcmp(&m.params, &expected, sizeof expected));
  EXPECT_EQ(0, std::memcmp(&m.joint, &arm->layers.sph.joint[0].model.joint, sizeof m.joint));
  EXPECT_EQ(l.layers.sph.joint[0].force_input, arm->layers.sph.joint[0].force_input);
  // A version this loader does not know is refused.
  put_u32(&l.bytes, section, 3);
  sinew::test::fix_crc(&l.bytes);
  EXPECT_NE(load_error(l.bytes).find("version"), std::string::npos);
}

// The writer: the arm's layers with [[sph]] surface_tension = 1 N/m compile
// to an SPHJ version 2 whose loaded gain is the builder's
// 6 sigma h dt^2 / (m C unit), and run in the pipeline.
TEST(LayerLoader, SphSurfaceTensionCompilesToVersion2) {
  sinew::rigc::RigSpec spec;
  sinew::layers::LayerSpecs specs;
  ASSERT_TRUE(sinew::rigc::builtin_rig("arm", sinew::rigc::SkinChoice::kDualQuaternion, &spec));
  ASSERT_TRUE(sinew::layers::builtin_layers("arm", &specs));
  ASSERT_EQ(specs.sph.size(), 1u);
  specs.sph[0].surface_tension = 1.0;
  LoadedLayers l;
  std::vector<std::string> report;
  std::string error;
  sinew::rigc::CompileReport core;
  ASSERT_TRUE(sinew::layers::add_layer_dofs(&spec, specs, &report, &error) &&
              sinew::rigc::compile_rig(spec, &l.bytes, &core, &error) &&
              sinew::layers::compile_layers(spec, specs, &l.bytes, &report, &error))
      << error;
  ASSERT_TRUE(l.load(&error)) << error;
  const size_t section = sinew::test::section_offset(l.bytes, sinew::sph::kSectionSphJoint);
  ASSERT_NE(section, 0u);
  EXPECT_EQ(get_u32(l.bytes, section), sinew::sph::kSphSectionVersion2);
  EXPECT_GT(l.layers.sph.joint[0].model.params.tension_gain, 0);
  pl::PipelineOptions options;
  ASSERT_TRUE(l.start(options, &error)) << error;
}
