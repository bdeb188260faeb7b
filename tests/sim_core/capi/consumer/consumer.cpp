// The same program as consumer.c, compiled as C++20 against the installed
// package (find_package(sinew), sinew::core): the C API is usable from C++,
// and the C++ headers are installed where the package says.
#include <sinew/sinew.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

#include "sim_core/pipeline/pipeline.hpp"  // the C++ API is installed too

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  std::FILE* f = std::fopen(argv[1], "rb");
  if (f == nullptr) return 2;
  std::fseek(f, 0, SEEK_END);
  const size_t size = static_cast<size_t>(std::ftell(f));
  std::fseek(f, 0, SEEK_SET);
  std::vector<uint64_t> blob(size / 8 + 1), rig_memory, layer_memory, pipeline_memory;
  if (std::fread(blob.data(), 1, size, f) != size) return 2;
  std::fclose(f);
  size_t bytes = 0;
  sinew_rig* rig = nullptr;
  sinew_pipeline* pipeline = nullptr;
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
  if (s.code != SINEW_OK) {
    std::fprintf(stderr, "consumer: %s\n", s.message);
    return 1;
  }
  const sinew_rig_info info = sinew_rig_get_info(rig);
  const sinew_vertices v = sinew_pipeline_vertices(pipeline);
  const int32_t rest_x = v.x[0], rest_y = v.y[0], rest_z = v.z[0];
  std::vector<int32_t> inputs(info.input_count + info.external_input_count, 0);
  for (int tick = 0; tick < 200; ++tick) {
    inputs[0] = static_cast<int32_t>(tick * 2000000);
    s = sinew_pipeline_step(pipeline, inputs.data(), inputs.size());
    if (s.code != SINEW_OK) {
      std::fprintf(stderr, "consumer: %s\n", s.message);
      return 1;
    }
  }
  uint64_t hash = 1469598103934665603u;
  for (const int32_t* axis : {v.x, v.y, v.z})
    for (uint32_t i = 0; i < v.count; ++i) {
      uint32_t w = static_cast<uint32_t>(axis[i]);
      for (int b = 0; b < 4; ++b, w >>= 8) hash = (hash ^ (w & 0xFF)) * 1099511628211u;
    }
  const bool moved = v.x[0] != rest_x || v.y[0] != rest_y || v.z[0] != rest_z;
  std::printf("joints %u inputs %u vertices %u layers %u moved %d checksum %016llx\n", info.joint_count,
              info.input_count, v.count, info.layer_count, moved ? 1 : 0, static_cast<unsigned long long>(hash));
  return moved ? 0 : 1;
}
