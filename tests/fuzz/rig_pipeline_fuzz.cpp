// libFuzzer target: a blob the rig and layer loaders accept must be safe to
// run. Any bytes as a rig blob (CRC fixed up by the harness); what loads is
// started with every layer it carries, at the rig's rate and at another, and
// stepped on extreme inputs and an extreme sampled pose (the sanitizers
// watch). Each input costs ten steps of every layer, so this target runs
// about a tenth as many inputs a second as rig_loader_fuzz, which fuzzes the
// same loaders without stepping.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rig_fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sinew::fuzz::LoadedInput in;
  if (!sinew::fuzz::load_rig_input(data, size, &in)) return 0;
  static sinew::pipeline::Pipeline pipeline;
  for (const uint32_t tick_hz : {0u, sinew::fuzz::other_tick_hz(size)}) {
    if (!sinew::fuzz::start_pipeline(in, tick_hz, &pipeline)) continue;
    std::vector<int32_t> inputs(pipeline.input_count, 0);
    const int32_t extremes[] = {0, INT32_MAX, INT32_MIN, 0x40000000};
    for (int32_t v : extremes) {
      for (int32_t& value : inputs) value = v;
      sinew::pipeline::pipeline_step(&pipeline, inputs);
    }
    // A sampled pose at the extremes (the pose-driven path).
    std::vector<sinew::skeleton::LocalPose> locals(in.rig.joint_count());
    for (auto& l : locals)
      l = {{INT32_MAX, INT32_MIN, INT32_MAX}, {0x20000000, -0x20000000, 0, 0}, {INT32_MIN, 1, INT32_MAX}};
    const std::vector<int32_t> external(in.layers.external_count(), INT32_MAX);
    sinew::pipeline::pipeline_step_locals(&pipeline, locals, external);
  }
  return 0;
}
