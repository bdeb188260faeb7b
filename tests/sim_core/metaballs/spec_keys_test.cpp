// The [metaballs] keys of a TOML rig spec (rigc): jiggle in physical units,
// jiggle and bulge regions, the overlap reach and action lines reach the
// builder's options; a compiled rig carries the physical jiggle's tick rate
// in its metaballs section, and the loaded model swings with the gains of
// that rate.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "host_tools/layers/metaballs/options.hpp"
#include "host_tools/layers/rig_layers.hpp"
#include "host_tools/rigc/quantize.hpp"
#include "host_tools/rigc/toml_spec.hpp"
#include "sim_core/metaballs/jiggle_gains.hpp"
#include "sim_core/pipeline/layer_format.hpp"
#include "sim_core/pipeline/layer_set.hpp"
#include "sim_core/rig/rig_format.hpp"
#include "tests/sim_core/pipeline/pipeline_fixture.hpp"
#include "tests/support/temp_path.hpp"

namespace {

using sinew::test::LoadedLayers;

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
  const std::string path = sinew::test::process_temp_path(name);
  std::ofstream(path) << text;
  return path;
}

// Compiles the spec `text` (written to a temporary file `name`, as rigc
// reads it) into a blob and the layer tables it read.
bool compile(const std::string& name, const std::string& text, std::vector<uint8_t>* blob,
             sinew::layers::LayerSpecs* layers, std::string* error) {
  const std::string path = write_spec(name, text);
  sinew::rigc::RigSpec spec;
  sinew::rigc::CompileReport core;
  std::vector<std::string> report;
  const bool ok = sinew::rigc::load_toml_rig(path, &spec, layers, error) &&
                  sinew::layers::add_layer_dofs(&spec, *layers, &report, error) &&
                  sinew::rigc::compile_rig(spec, blob, &core, error) &&
                  sinew::layers::compile_layers(spec, *layers, blob, &report, error);
  std::filesystem::remove(path);
  return ok;
}

TEST(MetaballsSpecKeys, PhysicalJiggleBulgeAndOverlapKeysReachTheLoadedModel) {
  std::vector<uint8_t> bytes;
  sinew::layers::LayerSpecs layers;
  std::string error;
  ASSERT_TRUE(compile("sinew_metaballs_keys.toml", kSpec, &bytes, &layers, &error)) << error;
  const auto& o = layers.metaballs.options;
  EXPECT_EQ(o.jiggle_frequency, 3.0);
  EXPECT_EQ(o.jiggle_window, 0.5);
  EXPECT_EQ(o.overlap_reach, 1.5);  // not the default (0)
  ASSERT_EQ(o.jiggle.size(), 1u);
  ASSERT_EQ(o.bulge.size(), 1u);
  EXPECT_EQ(o.bulge[0].gain, 0.2);

  LoadedLayers loaded;
  loaded.bytes = bytes;
  ASSERT_TRUE(loaded.load(&error)) << error;
  ASSERT_TRUE(loaded.layers.metaballs.present);
  const auto& m = loaded.layers.metaballs.model;
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

// Jiggle is in physical units by default: a jiggle region without
// jiggle_frequency swings at the default frequency and window for the
// spec's rate; jiggle_frequency = 0 asks for the per-step gains; a
// [metaballs] table without jiggle regions is the same either way (its
// section carries no rate and keeps its bytes).
const char* const kJiggleOnlySpec = R"(
[rig]
source = "builtin:arm"
skinning = "dqs"
rate_hz = 500

[metaballs]
)";
const char* const kRegion = R"(
[[metaballs.jiggle]]
bone = "shoulder"
from = 0.3
to = 0.7
stiffness = 0.05
)";

TEST(MetaballsSpecKeys, JiggleIsInPhysicalUnitsByDefault) {
  std::vector<uint8_t> bytes;
  sinew::layers::LayerSpecs layers;
  std::string error;
  ASSERT_TRUE(
      compile("sinew_metaballs_default_jiggle.toml", std::string(kJiggleOnlySpec) + kRegion, &bytes, &layers, &error))
      << error;
  const sinew::metaballs_build::Options defaults;
  EXPECT_GT(defaults.jiggle_frequency, 0);
  LoadedLayers loaded;
  loaded.bytes = bytes;
  ASSERT_TRUE(loaded.load(&error)) << error;
  const auto& m = loaded.layers.metaballs.model;
  EXPECT_EQ(m.jiggle_rate_hz, 500u);
  sinew::metaballs::JiggleGains want;
  ASSERT_TRUE(sinew::metaballs::jiggle_gains(sinew::rigc::to_fixed(defaults.jiggle_frequency, 16),
                                             sinew::rigc::to_fixed(defaults.jiggle_window, 16), 500, &want));
  EXPECT_EQ(m.jiggle_damping, want.damping);
  size_t jiggling = 0;
  for (const auto k : m.ball_jiggle)
    if (k != 0) {
      EXPECT_EQ(k, want.stiffness);
      ++jiggling;
    }
  EXPECT_GT(jiggling, 0u);
  std::printf("default jiggle: %zu balls swing at %.1f Hz within %.2f s (k %d, d %d at 500 Hz)\n", jiggling,
              defaults.jiggle_frequency, defaults.jiggle_window, want.stiffness, want.damping);
}

TEST(MetaballsSpecKeys, JiggleFrequencyZeroKeepsThePerStepGains) {
  std::vector<uint8_t> bytes;
  sinew::layers::LayerSpecs layers;
  std::string error;
  ASSERT_TRUE(compile("sinew_metaballs_step_jiggle.toml",
                      std::string(kJiggleOnlySpec) + "jiggle_frequency = 0\njiggle_damping = 0.95\n" + kRegion, &bytes,
                      &layers, &error))
      << error;
  LoadedLayers loaded;
  loaded.bytes = bytes;
  ASSERT_TRUE(loaded.load(&error)) << error;
  const auto& m = loaded.layers.metaballs.model;
  EXPECT_EQ(m.jiggle_rate_hz, 0u);
  EXPECT_EQ(m.jiggle_damping, sinew::rigc::to_fixed(0.95, 30));
  size_t jiggling = 0;
  for (const auto k : m.ball_jiggle)
    if (k != 0) {
      EXPECT_EQ(k, sinew::rigc::to_fixed(0.05, 30));
      ++jiggling;
    }
  EXPECT_GT(jiggling, 0u);
}

TEST(MetaballsSpecKeys, NoJiggleRegionsNoRateAndTheSameBytes) {
  std::vector<uint8_t> by_default, per_step;
  sinew::layers::LayerSpecs layers;
  std::string error;
  ASSERT_TRUE(compile("sinew_metaballs_no_jiggle.toml", kJiggleOnlySpec, &by_default, &layers, &error)) << error;
  ASSERT_TRUE(compile("sinew_metaballs_no_jiggle0.toml", std::string(kJiggleOnlySpec) + "jiggle_frequency = 0\n",
                      &per_step, &layers, &error))
      << error;
  EXPECT_EQ(by_default, per_step);
  LoadedLayers loaded;
  loaded.bytes = by_default;
  ASSERT_TRUE(loaded.load(&error)) << error;
  EXPECT_EQ(loaded.layers.metaballs.model.jiggle_rate_hz, 0u);
}

TEST(MetaballsSpecKeys, UnknownKeyIsRefused) {
  std::vector<uint8_t> bytes;
  sinew::layers::LayerSpecs layers;
  std::string error;
  EXPECT_FALSE(
      compile("sinew_metaballs_typo.toml", std::string(kSpec) + "jigle_window = 1\n", &bytes, &layers, &error));
  EXPECT_NE(error.find("unknown key"), std::string::npos) << error;
}

// The MBAL section's layer version of a compiled blob (0: none).
uint32_t metaballs_section_version(const std::vector<uint8_t>& bytes) {
  const size_t at = sinew::test::section_offset(bytes, sinew::metaballs::kSectionMetaballs);
  if (at == 0) return 0;
  sinew::pipeline::LayerSectionHeader lh;
  std::memcpy(&lh, bytes.data() + at, sizeof(lh));
  return lh.layer_version;
}

// kSpec without what only layer version 3 carries: the coupling springs of
// its jiggle region and overlap between bones that share no joint.
std::string uncoupled_spec() {
  std::string text = kSpec;
  const std::string key = "jiggle_window = 0.5\n";
  text.insert(text.find(key) + key.size(), "jiggle_coupling = 0\noverlap_between_bones = false\n");
  return text;
}

TEST(MetaballsSpecKeys, ActionLinesGoIntoTheRigFormatAsLayerVersion2) {
  const std::string text =
      uncoupled_spec() +
      "\n[[metaballs.action_line]]\norigin = \"shoulder\"\ninsertion = \"elbow\"\nside = [0, 0.03, 0]\n";
  std::vector<uint8_t> bytes, plain;
  sinew::layers::LayerSpecs layers, plain_layers;
  std::string error;
  ASSERT_TRUE(compile("sinew_metaballs_lines.toml", text, &bytes, &layers, &error)) << error;
  ASSERT_EQ(layers.metaballs.options.action_lines.size(), 1u);
  EXPECT_EQ(layers.metaballs.options.action_lines[0].side[1], 0.03);
  // Without action lines the section stays version 1 (the bytes of existing
  // rigs); with them it is version 2.
  ASSERT_TRUE(compile("sinew_metaballs_plain.toml", uncoupled_spec(), &plain, &plain_layers, &error)) << error;
  EXPECT_EQ(metaballs_section_version(plain), 1u);
  EXPECT_EQ(metaballs_section_version(bytes), sinew::metaballs::kMetaballsSectionVersion2);

  LoadedLayers loaded;
  loaded.bytes = bytes;
  ASSERT_TRUE(loaded.load(&error)) << error;
  ASSERT_TRUE(loaded.layers.metaballs.present);
  const auto& m = loaded.layers.metaballs.model;
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

// Physical jiggle couples its balls to their neighbours by springs of
// jiggle_coupling Hz (default: the builder's), which only layer version 3
// carries: a version 2 reader would take their stiffness per step.
TEST(MetaballsSpecKeys, CoupledJiggleGoesIntoTheRigFormatAsLayerVersion3) {
  std::string coupled = kSpec;
  const std::string key = "jiggle_window = 0.5\n";
  coupled.insert(coupled.find(key) + key.size(), "jiggle_coupling = 2.5\n");
  std::vector<uint8_t> bytes;
  sinew::layers::LayerSpecs layers;
  std::string error;
  ASSERT_TRUE(compile("sinew_metaballs_coupled.toml", coupled, &bytes, &layers, &error)) << error;
  EXPECT_EQ(layers.metaballs.options.jiggle_coupling, 2.5);
  EXPECT_EQ(metaballs_section_version(bytes), sinew::metaballs::kMetaballsSectionVersion3);
  LoadedLayers loaded;
  loaded.bytes = bytes;
  ASSERT_TRUE(loaded.load(&error)) << error;
  const auto& m = loaded.layers.metaballs.model;
  ASSERT_FALSE(m.pairs.empty());
  // x = (2 pi 2.5 / 500)^2 for every pair, each with a jiggle ball.
  const sinew::fx::Unit x = sinew::metaballs::coupling_stiffness(static_cast<int32_t>(2.5 * 65536), 500);
  EXPECT_NEAR(std::ldexp(x, -30), std::pow(2 * 3.141592653589793 * 2.5 / 500, 2), 1e-8);
  for (const auto& p : m.pairs) {
    EXPECT_EQ(p.stiffness, x);
    EXPECT_TRUE(m.ball_jiggle[p.a] != 0 || m.ball_jiggle[p.b] != 0);
  }
  // The same section stamped version 2 would have its couplings read as
  // per-step gains by an older reader's rules: refused naming the pairs.
  std::vector<uint8_t> relabelled = bytes;
  const size_t at = sinew::test::section_offset(relabelled, sinew::metaballs::kSectionMetaballs);
  ASSERT_NE(at, 0u);
  sinew::pipeline::LayerSectionHeader lh;
  std::memcpy(&lh, relabelled.data() + at, sizeof(lh));
  lh.layer_version = sinew::metaballs::kMetaballsSectionVersion2;
  std::memcpy(relabelled.data() + at, &lh, sizeof(lh));
  sinew::test::fix_crc(&relabelled);
  LoadedLayers old_reader;
  old_reader.bytes = relabelled;
  EXPECT_FALSE(old_reader.load(&error));
  EXPECT_NE(error.find("layer version 3"), std::string::npos) << error;
  // Too stiff for the rate: refused naming the key.
  std::string stiff = kSpec;
  stiff.insert(stiff.find(key) + key.size(), "jiggle_coupling = 90\n");
  EXPECT_FALSE(compile("sinew_metaballs_stiff.toml", stiff, &bytes, &layers, &error));
  EXPECT_NE(error.find("jiggle_coupling"), std::string::npos) << error;
}

}  // namespace
