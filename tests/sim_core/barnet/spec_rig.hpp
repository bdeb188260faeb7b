// A rig spec (TOML, rigc) compiled with its layer tables, loaded as the board
// loads it and run through the pipeline: the bar-net spec tests' harness.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
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
#include "tests/support/temp_path.hpp"

namespace sinew::test::barnet {

namespace pl = sinew::pipeline;

struct SpecRig {
  std::vector<uint8_t> bytes;
  std::vector<uint64_t> blob, arena, layer_arena, pipeline_arena;
  sinew::rigc::RigSpec spec;  // with the layers' DOFs added
  std::vector<std::string> input_names;
  sinew::rig::Rig rig;
  pl::LayerSet layers;
  pl::Pipeline pipeline;
  pl::PipelineOptions options;
  std::string error;
  size_t elbow = 0;                              // the first input whose name starts with "elbow" (builtin:arm specs)
  std::vector<int32_t> angles, external_values;  // the last tick's inputs

  // Compiles the spec at `path` (a [rig] source is relative to its folder).
  bool compile_file(const std::string& path) {
    sinew::layers::LayerSpecs specs;
    sinew::rigc::CompileReport core;
    std::vector<std::string> report;
    spec = {};
    bytes.clear();
    if (!(sinew::rigc::load_toml_rig(path, &spec, &specs, &error) &&
          sinew::layers::add_layer_dofs(&spec, specs, &report, &error) &&
          sinew::rigc::compile_rig(spec, &bytes, &core, &error) &&
          sinew::layers::compile_layers(spec, specs, &bytes, &report, &error)))
      return false;
    input_names = sinew::rigc::input_names(spec);
    while (elbow < input_names.size() && input_names[elbow].rfind("elbow", 0) != 0) ++elbow;
    return load();
  }

  // Compiles spec text (written to a temporary file: builtin rigs only).
  bool compile_and_load(const char* text) {
    const std::string path = sinew::test::process_temp_path("barnet_keys.toml");
    std::ofstream(path) << text;
    const bool ok = compile_file(path);
    std::filesystem::remove(path);
    return ok;
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
    const size_t pb = pl::pipeline_state_bytes(rig, layers, options);
    pipeline_arena.assign(pb / 8 + 1, 0);
    const pl::PipelineStatus ps = pl::pipeline_init(rig, layers, options, pipeline_arena.data(), pb + 8, &pipeline);
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
      if (e.id == sinew::barnet::kSectionBarnet) return e.offset;
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

  // One pipeline tick on the rig's inputs then its external values.
  bool tick(const std::vector<int32_t>& inputs, const std::vector<int32_t>& external) {
    std::vector<int32_t> all = inputs;
    all.resize(rig.input_count, 0);
    all.insert(all.end(), external.begin(), external.end());
    all.resize(rig.input_count + layers.external_count(), 0);
    const auto split = static_cast<std::ptrdiff_t>(rig.input_count);
    angles.assign(all.begin(), all.begin() + split);
    external_values.assign(all.begin() + split, all.end());
    const pl::PipelineStatus s = pl::pipeline_step(&pipeline, all);
    EXPECT_TRUE(s.ok()) << s.message;
    return s.ok();
  }

  // One tick at the given elbow angle (degrees) and external values; the
  // first net's largest node move.
  int32_t step(double elbow_degrees, std::vector<int32_t> external) {
    std::vector<int32_t> inputs(rig.input_count, 0);
    inputs[elbow] = static_cast<int32_t>(std::llround(elbow_degrees / 360.0 * 4294967296.0));
    tick(inputs, external);
    return pipeline.barnet.net[0].stats.max_displacement;
  }
};

}  // namespace sinew::test::barnet
