// The same program as consumer.c, compiled as C++20 against the installed
// package (find_package(sinew), sinew::core): the C API is usable from C++,
// and the C++ headers are installed where the package says.
#include <sinew/sinew.h>

#include <cstdio>
#include <vector>

#include "consumer_pipeline.hpp"
#include "sim_core/pipeline/pipeline.hpp"  // the C++ API is installed too

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  ConsumerPipeline c;
  if (!c.load(argv[1])) return 1;
  const sinew_rig_info info = sinew_rig_get_info(c.rig);
  const sinew_vertices v = sinew_pipeline_vertices(c.pipeline);
  const int32_t rest_x = v.x[0], rest_y = v.y[0], rest_z = v.z[0];
  std::vector<int32_t> inputs(info.input_count + info.external_input_count, 0);
  for (int tick = 0; tick < 200; ++tick) {
    inputs[0] = static_cast<int32_t>(tick * 2000000);
    const sinew_status s = sinew_pipeline_step(c.pipeline, inputs.data(), inputs.size());
    if (s.code != SINEW_OK) {
      std::fprintf(stderr, "consumer: %s\n", s.message);
      return 1;
    }
  }
  const bool moved = v.x[0] != rest_x || v.y[0] != rest_y || v.z[0] != rest_z;
  c.print(moved);
  return moved ? 0 : 1;
}
