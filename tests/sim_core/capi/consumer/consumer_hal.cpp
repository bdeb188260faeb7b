// The installed core and hal together (find_package(sinew COMPONENTS hal),
// sinew::core and sinew::hal): the pipeline stepped through the C API, each
// tick's skin written as a pose frame by hal's frame-log writer, and the log
// read back by hal's reader, which must return every frame word for word.
// Prints the same line as consumer.c, so the test compares them.
#include <sinew/sinew.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "hal/output/frame_log_reader.hpp"
#include "hal/output/frame_log_writer.hpp"

namespace {

bool load(const char* path, std::vector<uint64_t>* blob, size_t* size) {
  std::FILE* f = std::fopen(path, "rb");
  if (f == nullptr) return false;
  std::fseek(f, 0, SEEK_END);
  *size = static_cast<size_t>(std::ftell(f));
  std::fseek(f, 0, SEEK_SET);
  blob->resize(*size / 8 + 1);
  const bool ok = std::fread(blob->data(), 1, *size, f) == *size;
  std::fclose(f);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: consumer_hal RIG LOG\n");
    return 2;
  }
  std::vector<uint64_t> blob, rig_memory, layer_memory, pipeline_memory;
  size_t size = 0, bytes = 0;
  if (!load(argv[1], &blob, &size)) return 2;
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
    std::fprintf(stderr, "consumer_hal: %s\n", s.message);
    return 1;
  }
  const sinew_rig_info info = sinew_rig_get_info(rig);
  const sinew_vertices v = sinew_pipeline_vertices(pipeline);
  const int32_t rest_x = v.x[0], rest_y = v.y[0], rest_z = v.z[0];
  std::vector<int32_t> inputs(info.input_count + info.external_input_count, 0);
  std::vector<uint8_t> input_status(inputs.size(), 0);

  sinew::hal::PoseFrame frame;
  frame.vertex_count = v.count;
  frame.position[0] = v.x;
  frame.position[1] = v.y;
  frame.position[2] = v.z;
  frame.input_count = static_cast<uint32_t>(inputs.size());
  frame.input_value = inputs.data();
  frame.input_status = input_status.data();
  std::remove(argv[2]);
  sinew::hal::output::FrameLogWriter writer;
  std::string error;
  if (!writer.open(argv[2], sinew::hal::output::shape_of(frame), {}, &error)) {
    std::fprintf(stderr, "consumer_hal: %s\n", error.c_str());
    return 1;
  }
  constexpr int kTicks = 200;
  std::vector<int32_t> last_x;
  for (int tick = 0; tick < kTicks; ++tick) {
    inputs[0] = static_cast<int32_t>(tick * 2000000);
    s = sinew_pipeline_step(pipeline, inputs.data(), inputs.size());
    if (s.code != SINEW_OK) {
      std::fprintf(stderr, "consumer_hal: %s\n", s.message);
      return 1;
    }
    frame.tick = static_cast<uint64_t>(tick);
    frame.timestamp_ns = static_cast<uint64_t>(tick) * 1000000u;
    if (!writer.write(frame)) {
      std::fprintf(stderr, "consumer_hal: frame %d not written\n", tick);
      return 1;
    }
  }
  writer.close();

  sinew::hal::output::FrameLogReader reader;
  if (!reader.open(argv[2], &error)) {
    std::fprintf(stderr, "consumer_hal: %s\n", error.c_str());
    return 1;
  }
  sinew::hal::output::DecodedPose pose;
  int frames = 0;
  while (reader.next(&pose)) ++frames;
  const bool same = frames == kTicks && reader.clean_end() && pose.vertex_count == v.count &&
                    std::vector<int32_t>(v.x, v.x + v.count) == pose.position[0] &&
                    std::vector<int32_t>(v.y, v.y + v.count) == pose.position[1] &&
                    std::vector<int32_t>(v.z, v.z + v.count) == pose.position[2];
  if (!same) {
    std::fprintf(stderr, "consumer_hal: read back %d of %d frames (%s), last %s\n", frames, kTicks,
                 reader.stop_message().c_str(), frames > 0 ? "differs" : "missing");
    return 1;
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
