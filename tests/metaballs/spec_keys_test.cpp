// The [metaballs] keys of a TOML rig spec (rigc): jiggle in physical units,
// jiggle and bulge regions, the overlap reach and action lines reach the
// builder's options; a compiled rig carries the physical jiggle's tick rate
// in its metaballs section, and the loaded model swings with the gains of
// that rate.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "host_tools/layers/rig_layers.hpp"
#include "host_tools/rigc/toml_spec.hpp"
#include "sim_core/metaballs/jiggle_gains.hpp"
#include "sim_core/pipeline/layer_format.hpp"
#include "sim_core/pipeline/layer_set.hpp"
#include "sim_core/rig/rig_format.hpp"

namespace {

const char* const kSpec = R"(
[rig]
source = "builtin:arm"
skinning = "dqs"
rate_hz = 500

[metaballs]
jiggle_frequency = 3.0
jiggle_window = 0.5
overlap_reach = 1.5

[[metaballs.jiggle]]
bone = "shoulder"
from = 0.3
to = 0.7

[[metaballs.bulge]]
bone = "shoulder"
from = 0.3
to = 0.7
angle_a = "shoulder"
angle_b = "elbow"
gain = 0.2
)";

std::string write_spec(const std::string& name, const std::string& text) {
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  std::ofstream(path) << text;
  return path;
}

bool compile(const std::string& path, std::vector<uint8_t>* blob, sinew::layers::LayerSpecs* layers,
             std::string* error) {
  sinew::rigc::RigSpec spec;
  sinew::rigc::CompileReport core;
  std::vector<std::string> report;
  return sinew::rigc::load_toml_rig(path, &spec, layers, error) &&
         sinew::layers::add_layer_dofs(&spec, *layers, &report, error) &&
         sinew::rigc::compile_rig(spec, blob, &core, error) &&
         sinew::layers::compile_layers(spec, *layers, blob, &report, error);
}

TEST(MetaballsSpecKeys, PhysicalJiggleBulgeAndOverlapKeysReachTheLoadedModel) {
  const std::string path = write_spec("sinew_metaballs_keys.toml", kSpec);
  std::vector<uint8_t> bytes;
  sinew::layers::LayerSpecs layers;
  std::string error;
  const bool ok = compile(path, &bytes, &layers, &error);
  std::filesystem::remove(path);
  ASSERT_TRUE(ok) << error;
  const auto& o = layers.metaballs.options;
  EXPECT_EQ(o.jiggle_frequency, 3.0);
  EXPECT_EQ(o.jiggle_window, 0.5);
  EXPECT_EQ(o.overlap_reach, 1.5);  // not the default (0)
  ASSERT_EQ(o.jiggle.size(), 1u);
  ASSERT_EQ(o.bulge.size(), 1u);
  EXPECT_EQ(o.bulge[0].gain, 0.2);

  std::vector<uint64_t> blob(bytes.size() / 8 + 1, 0), arena, layer_arena;
  std::memcpy(blob.data(), bytes.data(), bytes.size());
  const auto* p = reinterpret_cast<const uint8_t*>(blob.data());
  size_t a = 0, b = 0;
  sinew::rig::Rig rig;
  sinew::pipeline::LayerSet set;
  sinew::rig::LoadStatus st = sinew::rig::rig_validate(p, bytes.size(), &a);
  arena.assign(a / 8 + 1, 0);
  if (st.ok()) st = sinew::rig::rig_init(p, bytes.size(), arena.data(), arena.size() * 8, &rig);
  if (st.ok()) st = sinew::pipeline::layers_validate(rig, p, bytes.size(), &b);
  layer_arena.assign(b / 8 + 1, 0);
  if (st.ok())
    st = sinew::pipeline::layers_init(rig, p, bytes.size(), layer_arena.data(), layer_arena.size() * 8, &set);
  ASSERT_TRUE(st.ok()) << st.message;
  ASSERT_TRUE(set.has_metaballs);
  const auto& m = set.metaballs;
  // The section says which rate its gains are for: the spec's rate_hz.
  EXPECT_EQ(m.jiggle_rate_hz, 500u);
  sinew::metaballs::JiggleGains want;
  ASSERT_TRUE(sinew::metaballs::jiggle_gains(3 << 16, 1 << 15, 500, &want));
  EXPECT_EQ(m.jiggle_damping, want.damping);
  size_t jiggling = 0;
  for (const auto k : m.ball_jiggle) {
    if (k == 0) continue;
    EXPECT_EQ(k, want.stiffness);
    ++jiggling;
  }
  EXPECT_GT(jiggling, 0u);
  EXPECT_FALSE(m.bulges.empty());
  std::printf("spec keys: %zu jiggle balls at %u Hz (k %d, d %d), %zu bulging balls, %zu overlap candidates\n",
              jiggling, m.jiggle_rate_hz, want.stiffness, want.damping, m.bulges.size(), m.overlap_vertices.size());
}

TEST(MetaballsSpecKeys, UnknownKeyIsRefused) {
  std::vector<uint8_t> bytes;
  sinew::layers::LayerSpecs layers;
  std::string error;
  const std::string typo = write_spec("sinew_metaballs_typo.toml", std::string(kSpec) + "jigle_window = 1\n");
  EXPECT_FALSE(compile(typo, &bytes, &layers, &error));
  std::filesystem::remove(typo);
  EXPECT_NE(error.find("unknown key"), std::string::npos) << error;
}

// The MBAL section's layer version of a compiled blob (0: none).
uint32_t metaballs_section_version(const std::vector<uint8_t>& bytes) {
  sinew::rig::FileHeader h;
  std::memcpy(&h, bytes.data(), sizeof(h));
  for (uint32_t i = 0; i < h.section_count; ++i) {
    sinew::rig::SectionEntry e;
    std::memcpy(&e, bytes.data() + h.section_table_offset + size_t{i} * sizeof(e), sizeof(e));
    if (e.id != sinew::pipeline::kSectionMetaballs) continue;
    sinew::pipeline::LayerSectionHeader lh;
    std::memcpy(&lh, bytes.data() + e.offset, sizeof(lh));
    return lh.layer_version;
  }
  return 0;
}

TEST(MetaballsSpecKeys, ActionLinesGoIntoTheRigFormatAsLayerVersion2) {
  const std::string text =
      std::string(kSpec) +
      "\n[[metaballs.action_line]]\norigin = \"shoulder\"\ninsertion = \"elbow\"\nside = [0, 0.03, 0]\n";
  const std::string path = write_spec("sinew_metaballs_lines.toml", text);
  std::vector<uint8_t> bytes, plain;
  sinew::layers::LayerSpecs layers, plain_layers;
  std::string error;
  const bool ok = compile(path, &bytes, &layers, &error);
  std::filesystem::remove(path);
  ASSERT_TRUE(ok) << error;
  ASSERT_EQ(layers.metaballs.options.action_lines.size(), 1u);
  EXPECT_EQ(layers.metaballs.options.action_lines[0].side[1], 0.03);
  // Without action lines the section stays version 1 (the bytes of existing
  // rigs); with them it is version 2.
  const std::string plain_path = write_spec("sinew_metaballs_plain.toml", kSpec);
  ASSERT_TRUE(compile(plain_path, &plain, &plain_layers, &error)) << error;
  std::filesystem::remove(plain_path);
  EXPECT_EQ(metaballs_section_version(plain), 1u);
  EXPECT_EQ(metaballs_section_version(bytes), sinew::pipeline::kMetaballsSectionVersion2);

  std::vector<uint64_t> blob(bytes.size() / 8 + 1, 0), arena, layer_arena;
  std::memcpy(blob.data(), bytes.data(), bytes.size());
  const auto* p = reinterpret_cast<const uint8_t*>(blob.data());
  size_t a = 0, b = 0;
  sinew::rig::Rig rig;
  sinew::pipeline::LayerSet set;
  sinew::rig::LoadStatus st = sinew::rig::rig_validate(p, bytes.size(), &a);
  arena.assign(a / 8 + 1, 0);
  if (st.ok()) st = sinew::rig::rig_init(p, bytes.size(), arena.data(), arena.size() * 8, &rig);
  if (st.ok()) st = sinew::pipeline::layers_validate(rig, p, bytes.size(), &b);
  layer_arena.assign(b / 8 + 1, 0);
  if (st.ok())
    st = sinew::pipeline::layers_init(rig, p, bytes.size(), layer_arena.data(), layer_arena.size() * 8, &set);
  ASSERT_TRUE(st.ok()) << st.message;
  ASSERT_TRUE(set.has_metaballs);
  const auto& m = set.metaballs;
  ASSERT_EQ(m.action_lines.size(), 1u);
  EXPECT_FALSE(m.action_balls.empty());
  // The loaded line is the one the builder made from the same spec.
  const auto& line = m.action_lines[0];
  EXPECT_EQ(line.origin_bone, 0);     // shoulder
  EXPECT_EQ(line.insertion_bone, 1);  // elbow
  EXPECT_LT(line.origin_rest.y, line.origin_rest.x);
  EXPECT_GT(line.origin_rest.y, 0);  // the side shift
  for (const auto& ab : m.action_balls) EXPECT_EQ(ab.line, 0);
  std::printf("action lines in the rig format: %zu line, %zu action balls, MBAL version %u (%u without lines)\n",
              m.action_lines.size(), m.action_balls.size(), metaballs_section_version(bytes),
              metaballs_section_version(plain));
}

}  // namespace
