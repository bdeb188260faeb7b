// What rig_loader_fuzz and rig_pipeline_fuzz share: turning fuzzer bytes into
// a loaded rig. The CRC is recomputed so mutations reach the sections rather
// than stopping at the checksum, and the arenas are kept from one input to the
// next (grown, never shrunk) and filled with a pattern before each use: a
// fresh zeroed vector per input cost a third of the time in page faults and
// zeroing. A pattern rather than zeros, so that memory a loader forgets to
// set is not quietly zero.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "sim_core/pipeline/pipeline.hpp"
#include "sim_core/rig/crc32c.hpp"

namespace sinew::fuzz {

// 8-byte aligned bytes, as a blob read from a file is.
class Arena {
 public:
  void* take(size_t bytes) {
    const size_t words = bytes / 8 + 1;
    if (words_.size() < words) words_.resize(words);
    std::memset(words_.data(), 0xA5, words * 8);
    return words_.data();
  }
  size_t capacity_bytes() const { return words_.size() * 8; }

 private:
  std::vector<uint64_t> words_;
};

struct LoadedInput {
  rig::Rig rig;
  pipeline::LayerSet layers;
  const uint8_t* blob = nullptr;
  size_t size = 0;
};

// The blob with its CRC fixed up, validated and loaded (core and layer
// sections). False when a loader refuses it; traps when a loader accepts at
// validate and refuses at init, which the contract forbids.
inline bool load_rig_input(const uint8_t* data, size_t size, LoadedInput* out) {
  static Arena blob_arena, rig_arena, layer_arena;
  auto* bytes = static_cast<uint8_t*>(blob_arena.take(size));
  if (size > 0) std::memcpy(bytes, data, size);
  constexpr size_t kCrc = offsetof(rig::FileHeader, crc32c);
  if (size >= sizeof(rig::FileHeader)) {
    uint32_t total = 0;
    std::memcpy(&total, bytes + offsetof(rig::FileHeader, total_size), 4);
    if (total <= size && total >= kCrc + 4) {
      std::memset(bytes + kCrc, 0, 4);
      const uint32_t crc = rig::crc32c(0, bytes, total);
      std::memcpy(bytes + kCrc, &crc, 4);
    }
  }
  out->blob = bytes;
  out->size = size;
  size_t rig_bytes = 0, layer_bytes = 0;
  if (!rig::rig_validate(bytes, size, &rig_bytes).ok()) return false;
  void* rig_memory = rig_arena.take(rig_bytes);
  if (!rig::rig_init(bytes, size, rig_memory, rig_arena.capacity_bytes(), &out->rig).ok()) __builtin_trap();
  if (!pipeline::layers_validate(out->rig, bytes, size, &layer_bytes).ok()) return false;
  void* layer_memory = layer_arena.take(layer_bytes);
  return pipeline::layers_init(out->rig, bytes, size, layer_memory, layer_arena.capacity_bytes(), &out->layers).ok();
}

// Starts a pipeline with every layer `in` carries at `tick_hz` (0: the
// rig's rate), in an arena kept across inputs. False when pipeline_init
// refuses (a rate the layers cannot run at, say).
inline bool start_pipeline(const LoadedInput& in, uint32_t tick_hz, pipeline::Pipeline* out) {
  static Arena state_arena;
  pipeline::PipelineOptions options;
  options.tick_hz = tick_hz;
  void* state = state_arena.take(pipeline::pipeline_state_bytes(in.rig, in.layers, options));
  return pipeline::pipeline_init(in.rig, in.layers, options, state, state_arena.capacity_bytes(), out).ok();
}

// The two tick rates each input is started at: the rate the SPH gains were
// built for (0), then another (the gains are converted from the section's
// rate_hz, any u32; 13 Hz is the lowest SPH's substep limit allows).
inline uint32_t other_tick_hz(size_t size) { return 13u + static_cast<uint32_t>(size % 997); }

}  // namespace sinew::fuzz
