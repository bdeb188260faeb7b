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
#include "sim_core/pipeline/layer_set.hpp"

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

TEST(MetaballsSpecKeys, UnknownKeyAndActionLinesInACompiledRigAreRefused) {
  std::vector<uint8_t> bytes;
  sinew::layers::LayerSpecs layers;
  std::string error;
  const std::string typo = write_spec("sinew_metaballs_typo.toml", std::string(kSpec) + "jigle_window = 1\n");
  EXPECT_FALSE(compile(typo, &bytes, &layers, &error));
  std::filesystem::remove(typo);
  EXPECT_NE(error.find("unknown key"), std::string::npos) << error;
  const std::string lines = write_spec(
      "sinew_metaballs_lines.toml",
      std::string(kSpec) +
          "\n[[metaballs.action_line]]\norigin = \"shoulder\"\ninsertion = \"elbow\"\nside = [0, 0.03, 0]\n");
  bytes.clear();
  layers = {};
  EXPECT_FALSE(compile(lines, &bytes, &layers, &error));
  std::filesystem::remove(lines);
  EXPECT_NE(error.find("action lines"), std::string::npos) << error;
  ASSERT_EQ(layers.metaballs.options.action_lines.size(), 1u);
  EXPECT_EQ(layers.metaballs.options.action_lines[0].side[1], 0.03);
}

}  // namespace
