// libFuzzer target: any bytes as a rig blob, header, core sections and every
// layer section. The CRC is recomputed here so mutations reach the sections
// rather than stopping at the checksum. A blob the loaders accept must be
// safe to run: the pipeline is started with every layer it carries, at the
// rig's rate and at another, and stepped a few times on extreme inputs and
// extreme sampled poses (the sanitizers watch).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "sim_core/pipeline/pipeline.hpp"
#include "sim_core/rig/crc32c.hpp"

namespace {

void fix_crc(std::vector<uint8_t>* b) {
  constexpr size_t kCrc = offsetof(sinew::rig::FileHeader, crc32c);
  if (b->size() < sizeof(sinew::rig::FileHeader)) return;
  uint32_t total = 0;
  std::memcpy(&total, b->data() + offsetof(sinew::rig::FileHeader, total_size), 4);
  if (total > b->size() || total < kCrc + 4) return;
  std::memset(b->data() + kCrc, 0, 4);
  const uint32_t crc = sinew::rig::crc32c(0, b->data(), total);
  std::memcpy(b->data() + kCrc, &crc, 4);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> bytes(data, data + size);
  fix_crc(&bytes);
  std::vector<uint64_t> blob(size / 8 + 1);
  if (size > 0) std::memcpy(blob.data(), bytes.data(), size);
  const auto* p = reinterpret_cast<const uint8_t*>(blob.data());
  size_t rig_bytes = 0, layer_bytes = 0;
  if (!sinew::rig::rig_validate(p, size, &rig_bytes).ok()) return 0;
  std::vector<uint64_t> rig_arena(rig_bytes / 8 + 1);
  sinew::rig::Rig rig;
  if (!sinew::rig::rig_init(p, size, rig_arena.data(), rig_arena.size() * 8, &rig).ok()) __builtin_trap();
  if (!sinew::pipeline::layers_validate(rig, p, size, &layer_bytes).ok()) return 0;
  std::vector<uint64_t> layer_arena(layer_bytes / 8 + 1);
  sinew::pipeline::LayerSet layers;
  if (!sinew::pipeline::layers_init(rig, p, size, layer_arena.data(), layer_arena.size() * 8, &layers).ok()) return 0;
  // At the rate the SPH gains were built for, then at another (the gains are
  // converted from the section's rate_hz, any u32).
  for (const uint32_t tick_hz : {0u, 13u + static_cast<uint32_t>(size % 997)}) {
    sinew::pipeline::PipelineOptions options;
    options.tick_hz = tick_hz;
    std::vector<uint64_t> state(sinew::pipeline::pipeline_state_bytes(rig, layers, options) / 8 + 1);
    static sinew::pipeline::Pipeline pipeline;
    if (!sinew::pipeline::pipeline_init(rig, layers, options, state.data(), state.size() * 8, &pipeline).ok()) continue;
    std::vector<int32_t> inputs(pipeline.input_count, 0);
    const int32_t extremes[] = {0, INT32_MAX, INT32_MIN, 0x40000000};
    for (int32_t v : extremes) {
      for (int32_t& in : inputs) in = v;
      sinew::pipeline::pipeline_step(&pipeline, inputs);
    }
    // Sampled poses at the extremes (the pose-driven path).
    std::vector<sinew::skeleton::LocalPose> locals(rig.joint_count());
    for (auto& l : locals)
      l = {{INT32_MAX, INT32_MIN, INT32_MAX}, {0x20000000, -0x20000000, 0, 0}, {INT32_MIN, 1, INT32_MAX}};
    const std::vector<int32_t> external(layers.external_count(), INT32_MAX);
    sinew::pipeline::pipeline_step_locals(&pipeline, locals, external);
  }
  return 0;
}
