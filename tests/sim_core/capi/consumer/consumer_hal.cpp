// The installed core and hal together (find_package(sinew COMPONENTS hal),
// sinew::core and sinew::hal): the pipeline stepped through the C API, each
// tick's skin written as a pose frame by hal's frame-log writer, and the log
// read back by hal's reader, which must return every frame word for word.
// Prints the same line as consumer.c, so the test compares them.
#include <sinew/sinew.h>

#include <cstdio>
#include <string>
#include <vector>

#include "consumer_pipeline.hpp"
#include "hal/output/frame_log_reader.hpp"
#include "hal/output/frame_log_writer.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: consumer_hal RIG LOG\n");
    return 2;
  }
  ConsumerPipeline c;
  if (!c.load(argv[1])) return 1;
  const sinew_rig_info info = sinew_rig_get_info(c.rig);
  const sinew_vertices v = sinew_pipeline_vertices(c.pipeline);
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
    const sinew_status s = sinew_pipeline_step(c.pipeline, inputs.data(), inputs.size());
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

  const bool moved = v.x[0] != rest_x || v.y[0] != rest_y || v.z[0] != rest_z;
  c.print(moved);
  return moved ? 0 : 1;
}
