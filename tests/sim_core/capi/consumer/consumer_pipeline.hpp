// What the C++ consumers share: a compiled rig loaded and its pipeline
// initialised through the C API (sinew/sinew.h) in memory this object owns,
// and the line every consumer prints for the test to compare.
#pragma once

#include <sinew/sinew.h>

#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <vector>

struct ConsumerPipeline {
  std::vector<uint64_t> blob, rig_memory, layer_memory, pipeline_memory;
  sinew_rig* rig = nullptr;
  sinew_pipeline* pipeline = nullptr;

  // Loads the .rig at `path`; false (with the reason on stderr) when the
  // file cannot be read or the C API refuses it.
  bool load(const char* path) {
    std::FILE* f = std::fopen(path, "rb");
    if (f == nullptr) return false;
    std::fseek(f, 0, SEEK_END);
    const size_t size = static_cast<size_t>(std::ftell(f));
    std::fseek(f, 0, SEEK_SET);
    blob.resize(size / 8 + 1);
    const bool read = std::fread(blob.data(), 1, size, f) == size;
    std::fclose(f);
    if (!read) return false;
    size_t bytes = 0;
    sinew_status s = sinew_rig_bytes(blob.data(), size, &bytes);
    if (s.code == SINEW_OK) {
      rig_memory.resize(bytes / 8 + 1);
      s = sinew_rig_load(blob.data(), size, rig_memory.data(), bytes, &rig);
    }
    if (s.code == SINEW_OK) s = sinew_layers_bytes(rig, blob.data(), size, &bytes);
    if (s.code == SINEW_OK) {
      layer_memory.resize(bytes / 8 + 1);
      s = sinew_layers_load(rig, blob.data(), size, layer_memory.data(), bytes);
    }
    if (s.code == SINEW_OK) {
      bytes = sinew_pipeline_state_bytes(rig, nullptr);
      pipeline_memory.resize(bytes / 8 + 1);
      s = sinew_pipeline_init(rig, nullptr, pipeline_memory.data(), bytes, &pipeline);
    }
    if (s.code != SINEW_OK) std::fprintf(stderr, "consumer: %s\n", s.message);
    return s.code == SINEW_OK;
  }

  // "joints .. inputs .. vertices .. layers .. moved M checksum H" (FNV-1a
  // of the vertices' words), as consumer.c prints it.
  void print(bool moved) const {
    const sinew_rig_info info = sinew_rig_get_info(rig);
    const sinew_vertices v = sinew_pipeline_vertices(pipeline);
    uint64_t hash = 1469598103934665603u;
    for (const int32_t* axis : {v.x, v.y, v.z})
      for (uint32_t i = 0; i < v.count; ++i) {
        uint32_t w = static_cast<uint32_t>(axis[i]);
        for (int b = 0; b < 4; ++b, w >>= 8) hash = (hash ^ (w & 0xFF)) * 1099511628211u;
      }
    std::printf("joints %u inputs %u vertices %u layers %u moved %d checksum %016llx\n", info.joint_count,
                info.input_count, v.count, info.layer_count, moved ? 1 : 0, static_cast<unsigned long long>(hash));
  }
};
