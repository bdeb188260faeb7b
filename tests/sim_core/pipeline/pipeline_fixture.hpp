// A compiled rig with its layers, loaded as the board loads it (rig_init +
// layers_init), and a pipeline over it. Shared by the pipeline tests.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "host_tools/layers/builtin_layers.hpp"
#include "sim_core/pipeline/pipeline.hpp"
#include "sim_core/rig/crc32c.hpp"

namespace sinew::test {

struct LoadedLayers {
  std::vector<uint8_t> bytes;  // the blob as compiled
  std::vector<uint64_t> blob, arena, layer_arena, state;
  rig::Rig rig;
  pipeline::LayerSet layers;
  pipeline::Pipeline pipeline;

  const uint8_t* data() const { return reinterpret_cast<const uint8_t*>(blob.data()); }

  // Loads `bytes` (into aligned memory); false with the loader's message.
  bool load(std::string* error) {
    blob.assign(bytes.size() / 8 + 1, 0);
    std::memcpy(blob.data(), bytes.data(), bytes.size());
    size_t rig_bytes = 0, layer_bytes = 0;
    rig::LoadStatus st = rig::rig_validate(data(), bytes.size(), &rig_bytes);
    if (st.ok()) {
      arena.assign(rig_bytes / 8 + 1, 0);
      st = rig::rig_init(data(), bytes.size(), arena.data(), arena.size() * 8, &rig);
    }
    if (st.ok()) st = pipeline::layers_validate(rig, data(), bytes.size(), &layer_bytes);
    if (st.ok()) {
      layer_arena.assign(layer_bytes / 8 + 1, 0);
      st = pipeline::layers_init(rig, data(), bytes.size(), layer_arena.data(), layer_arena.size() * 8, &layers);
    }
    if (!st.ok()) *error = st.message;
    return st.ok();
  }

  bool start(const pipeline::PipelineOptions& options, std::string* error) {
    state.assign(pipeline::pipeline_state_bytes(rig, layers, options) / 8 + 1, 0);
    const pipeline::PipelineStatus st =
        pipeline::pipeline_init(rig, layers, options, state.data(), state.size() * 8, &pipeline);
    if (!st.ok()) *error = st.message;
    return st.ok();
  }
};

// The built-in rig `name` with every layer it carries, loaded (not started).
inline std::unique_ptr<LoadedLayers> builtin_with_layers(const std::string& name, std::string* error) {
  auto l = std::make_unique<LoadedLayers>();
  std::vector<std::string> report;
  if (!layers::compile_builtin(name, &l->bytes, &report, error) || !l->load(error)) return nullptr;
  return l;
}

// `spec` with the layers `tables`, compiled as rigc compiles a rig spec and
// loaded (not started); null with the message.
inline std::unique_ptr<LoadedLayers> compiled_with_layers(rigc::RigSpec spec, const layers::LayerSpecs& tables,
                                                          std::string* error) {
  auto l = std::make_unique<LoadedLayers>();
  std::vector<std::string> report;
  rigc::CompileReport core;
  if (!layers::add_layer_dofs(&spec, tables, &report, error) || !rigc::compile_rig(spec, &l->bytes, &core, error) ||
      !layers::compile_layers(spec, tables, &l->bytes, &report, error) || !l->load(error))
    return nullptr;
  return l;
}

// The built-in arm with its layers, or a test failure with the message.
inline std::unique_ptr<LoadedLayers> arm_with_layers() {
  std::string error;
  auto arm = builtin_with_layers("arm", &error);
  if (arm == nullptr) ADD_FAILURE() << error;
  return arm;
}

// Rewrites a blob's CRC after a deliberate change, so the loader reaches the
// field the test corrupted.
inline void fix_crc(std::vector<uint8_t>* bytes) {
  constexpr size_t kCrc = offsetof(rig::FileHeader, crc32c);
  std::memset(bytes->data() + kCrc, 0, 4);
  const uint32_t crc = rig::crc32c(0, bytes->data(), bytes->size());
  std::memcpy(bytes->data() + kCrc, &crc, 4);
}

// Offset of the payload of layer section `id` (its `instance`-th), or 0.
inline size_t section_offset(const std::vector<uint8_t>& bytes, uint32_t id, uint32_t instance = 0) {
  rig::FileHeader h;
  std::memcpy(&h, bytes.data(), sizeof(h));
  for (uint32_t i = 0; i < h.section_count; ++i) {
    rig::SectionEntry e;
    std::memcpy(&e, bytes.data() + h.section_table_offset + i * sizeof(e), sizeof(e));
    if (e.id == id && instance-- == 0) return e.offset;
  }
  return 0;
}

// Angle in degrees as a signed binary angle input.
inline int32_t degrees(double d) { return static_cast<int32_t>(d / 360.0 * 4294967296.0); }

}  // namespace sinew::test
