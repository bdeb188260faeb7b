// The [[barnet]] input keys of a TOML rig spec (rigc), compiled, loaded and
// run through the pipeline: force_input and q_input declare their external
// inputs, the BNET section becomes layer version 2 and carries them, the
// ring loads follow the force input instead of the flexion, and a lower q
// from q_input gives a larger bulge (D is linear in q: half the q, twice the
// displacement of every free node, to the rounding of two solves). A net
// without the keys keeps the version-1 section.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "host_tools/layers/rig_layers.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "host_tools/rigc/toml_spec.hpp"
#include "sim_core/pipeline/layer_set.hpp"
#include "sim_core/pipeline/pipeline.hpp"
#include "sim_core/rig/crc32c.hpp"
#include "sim_core/rig/rig_format.hpp"

namespace {

namespace pl = sinew::pipeline;

const char* const kPlainSpec = R"(
[rig]
source = "builtin:arm"

[[barnet]]
joint = "elbow"
)";

const char* const kInputSpec = R"(
[rig]
source = "builtin:arm"

[[barnet]]
joint = "elbow"
force_input = "biceps.grip"
force_input_full = 20.0
q_input = "biceps.tone"
)";

struct BarnetRig {
  std::vector<uint8_t> bytes;
  std::vector<uint64_t> blob, arena, layer_arena, pipeline_arena;
  sinew::rig::Rig rig;
  pl::LayerSet layers;
  pl::Pipeline pipeline;
  std::string error;
  size_t elbow = 0;  // the elbow's flexion input

  bool compile_and_load(const char* text) {
    const std::string path = (std::filesystem::temp_directory_path() / "sinew_barnet_keys.toml").string();
    std::ofstream(path) << text;
    sinew::rigc::RigSpec spec;
    sinew::layers::LayerSpecs specs;
    sinew::rigc::CompileReport core;
    std::vector<std::string> report;
    const bool ok = sinew::rigc::load_toml_rig(path, &spec, &specs, &error) &&
                    sinew::layers::add_layer_dofs(&spec, specs, &report, &error) &&
                    sinew::rigc::compile_rig(spec, &bytes, &core, &error) &&
                    sinew::layers::compile_layers(spec, specs, &bytes, &report, &error);
    std::filesystem::remove(path);
    if (!ok) return false;
    const std::vector<std::string> names = sinew::rigc::input_names(spec);
    while (elbow < names.size() && names[elbow].rfind("elbow", 0) != 0) ++elbow;
    if (elbow == names.size()) return error = "no elbow input", false;
    return load();
  }

  // Rewrites the blob's CRC after a deliberate change to `bytes`, so the
  // loader reaches the changed field.
  void reseal() {
    constexpr size_t kCrc = offsetof(sinew::rig::FileHeader, crc32c);
    std::memset(bytes.data() + kCrc, 0, 4);
    const uint32_t crc = sinew::rig::crc32c(0, bytes.data(), bytes.size());
    std::memcpy(bytes.data() + kCrc, &crc, 4);
  }

  // Loads `bytes` (compiled, possibly altered since).
  bool load() {
    blob.assign(bytes.size() / 8 + 1, 0);
    std::memcpy(blob.data(), bytes.data(), bytes.size());
    const auto* p = reinterpret_cast<const uint8_t*>(blob.data());
    size_t a = 0, b = 0;
    sinew::rig::LoadStatus st = sinew::rig::rig_validate(p, bytes.size(), &a);
    arena.assign(a / 8 + 1, 0);
    if (st.ok()) st = sinew::rig::rig_init(p, bytes.size(), arena.data(), arena.size() * 8, &rig);
    if (st.ok()) st = pl::layers_validate(rig, p, bytes.size(), &b);
    layer_arena.assign(b / 8 + 1, 0);
    if (st.ok()) st = pl::layers_init(rig, p, bytes.size(), layer_arena.data(), layer_arena.size() * 8, &layers);
    if (!st.ok()) return error = st.message, false;
    const size_t pb = pl::pipeline_state_bytes(rig, layers, {});
    pipeline_arena.assign(pb / 8 + 1, 0);
    const pl::PipelineStatus ps = pl::pipeline_init(rig, layers, {}, pipeline_arena.data(), pb + 8, &pipeline);
    if (!ps.ok()) return error = ps.message, false;
    return true;
  }

  // Byte offset of the blob's first BNET section (0: none).
  size_t barnet_section_offset() const {
    sinew::rig::FileHeader f;
    std::memcpy(&f, bytes.data(), sizeof(f));
    for (uint32_t i = 0; i < f.section_count; ++i) {
      sinew::rig::SectionEntry e;
      std::memcpy(&e, bytes.data() + f.section_table_offset + i * sizeof(e), sizeof(e));
      if (e.id == pl::kSectionBarnet) return e.offset;
    }
    return 0;
  }

  // The layer_version of the blob's first BNET section (0: none).
  uint32_t barnet_section_version() const {
    const size_t at = barnet_section_offset();
    if (at == 0) return 0;
    pl::LayerSectionHeader h;
    std::memcpy(&h, bytes.data() + at, sizeof(h));
    return h.layer_version;
  }

  // One pipeline tick at the given elbow angle (degrees) and external values.
  int32_t step(double elbow_degrees, std::vector<int32_t> external) {
    std::vector<int32_t> inputs(rig.input_count, 0);
    inputs[elbow] = static_cast<int32_t>(std::llround(elbow_degrees / 360.0 * 4294967296.0));
    inputs.insert(inputs.end(), external.begin(), external.end());
    const pl::PipelineStatus s = pl::pipeline_step(&pipeline, inputs);
    EXPECT_TRUE(s.ok()) << s.message;
    return pipeline.barnet[0].stats.max_displacement;
  }
};

constexpr int32_t kQ16 = 1 << 16;

}  // namespace

TEST(BarnetSpecKeys, PlainNetKeepsTheVersionOneSection) {
  BarnetRig r;
  ASSERT_TRUE(r.compile_and_load(kPlainSpec)) << r.error;
  EXPECT_EQ(r.barnet_section_version(), 1u);
  ASSERT_EQ(r.layers.barnet_count, 1u);
  EXPECT_EQ(r.layers.barnet[0].external_count, 0u);
  EXPECT_TRUE(r.layers.barnet[0].q_inputs.empty());
  EXPECT_EQ(r.step(0, {}), 0) << "no flexion, no load: the skinned control mesh";
  EXPECT_GT(r.step(90, {}), 0) << "the ring loads follow the flexion";
}

TEST(BarnetSpecKeys, ForceAndForceDensityInputsDriveTheNet) {
  BarnetRig r;
  ASSERT_TRUE(r.compile_and_load(kInputSpec)) << r.error;
  EXPECT_EQ(r.barnet_section_version(), pl::kBarnetSectionVersion2);
  const uint32_t grip = pl::find_external_input(r.layers, "biceps.grip");
  const uint32_t tone = pl::find_external_input(r.layers, "biceps.tone");
  ASSERT_NE(grip, pl::kNoExternalInput);
  ASSERT_NE(tone, pl::kNoExternalInput);
  EXPECT_EQ(r.layers.external[grip].quantity, static_cast<uint32_t>(pl::InputQuantity::kForce));
  EXPECT_EQ(r.layers.external[tone].quantity, static_cast<uint32_t>(pl::InputQuantity::kScalar));
  const sinew::barnet::BarnetModel& m = r.layers.barnet[0];
  EXPECT_EQ(m.external_count, r.layers.external_count());
  ASSERT_FALSE(m.loads.empty());
  for (const sinew::barnet::LoadRecord& l : m.loads) EXPECT_EQ(l.input, r.rig.input_count + grip);
  ASSERT_EQ(m.q_inputs.size(), 1u);
  EXPECT_EQ(m.q_inputs[0].bar_count, m.bars.size());

  std::vector<int32_t> external(r.layers.external_count(), 0);
  external[tone] = kQ16;
  EXPECT_LE(r.step(120, external), 1) << "flexion alone no longer loads the net";
  external[grip] = 20 * kQ16;
  const int32_t stiff = r.step(0, external);
  external[tone] = kQ16 / 2;
  const int32_t soft = r.step(0, external);
  external[grip] = 10 * kQ16;
  const int32_t soft_half = r.step(0, external);
  std::printf("elbow net from inputs: largest node move %d LSB at q, %d at q/2, %d at q/2 and half the force\n", stiff,
              soft, soft_half);
  EXPECT_GT(stiff, 1000) << "the full grip must bulge the net";
  EXPECT_NEAR(soft, 2 * stiff, 3) << "half the force density, twice the bulge (D linear in q)";
  EXPECT_NEAR(2 * soft_half, soft, 3) << "the load is linear in the input's value";
}

TEST(BarnetSpecKeys, VersionTwoSectionWithAWrongExternalCountIsRefused) {
  // A version-2 BNET section records how many external inputs its net was
  // built for; a count other than the rig's EXTI count would let a load or
  // a q_inputs record read past the step's external span (or another
  // input), so the loader refuses it and names the field.
  BarnetRig r;
  ASSERT_TRUE(r.compile_and_load(kInputSpec)) << r.error;
  const uint32_t rig_count = r.layers.external_count();
  ASSERT_EQ(rig_count, 2u);
  const size_t field =
      r.barnet_section_offset() + sizeof(pl::LayerSectionHeader) + offsetof(pl::BarnetSectionParams, external_count);
  uint32_t written = 0;
  std::memcpy(&written, r.bytes.data() + field, sizeof(written));
  ASSERT_EQ(written, rig_count) << "the compiled section carries the rig's count";
  const std::vector<uint8_t> good = r.bytes;
  for (const uint32_t wrong : {0u, 1u, 3u, 64u, 0xFFFFFFFFu}) {
    r.bytes = good;
    std::memcpy(r.bytes.data() + field, &wrong, sizeof(wrong));
    r.reseal();
    EXPECT_FALSE(r.load()) << "external_count " << wrong;
    EXPECT_NE(r.error.find("BNET#0.external_count: differs from the rig's external inputs (EXTI)"), std::string::npos)
        << "external_count " << wrong << ": " << r.error;
  }
  r.bytes = good;
  EXPECT_TRUE(r.load()) << r.error;
}

TEST(BarnetSpecKeys, NetKeySelectsThePapersArmNets) {
  // net = "arm-muscles" (Figure 3: 12 free nodes) and "arm-wrinkles"
  // (Figure 6: the fine mesh's vertices) on the built-in arm, through the
  // pipeline: the bind pose leaves the skinned mesh, flexion moves the net.
  for (const char* net : {"arm-muscles", "arm-wrinkles"}) {
    const std::string text =
        std::string("[rig]\nsource = \"builtin:arm\"\n\n[[barnet]]\njoint = \"elbow\"\nnet = \"") + net + "\"\n";
    BarnetRig r;
    ASSERT_TRUE(r.compile_and_load(text.c_str())) << net << ": " << r.error;
    ASSERT_EQ(r.layers.barnet_count, 1u);
    const sinew::barnet::BarnetModel& m = r.layers.barnet[0];
    uint32_t free = 0;
    for (const sinew::barnet::NodeRecord& n : m.nodes) free += n.kind == 0 ? 1u : 0u;
    EXPECT_EQ(free, std::string(net) == "arm-muscles" ? 12u : 77u) << net;
    EXPECT_EQ(r.step(0, {}), 0) << net << ": no flexion, no load";
    EXPECT_GT(r.step(150, {}), 1000) << net << ": the loads follow the flexion";
  }
  BarnetRig bad;
  EXPECT_FALSE(bad.compile_and_load("[rig]\nsource = \"builtin:arm\"\n\n[[barnet]]\njoint = \"elbow\"\nnet = \"x\"\n"));
  EXPECT_NE(bad.error.find("net must be"), std::string::npos) << bad.error;
}
