// libFuzzer target: any bytes as a rig blob, header, core sections and every
// layer section (the CRC is fixed up by the harness). What the loaders accept
// is then started as a pipeline with every layer it carries, at the rig's
// rate and at another: pipeline_init checks the layers against each other and
// the rate. Stepping the accepted blobs is rig_pipeline_fuzz's subject; this
// target stays on the parsers, at the rate a parser campaign needs.
#include <cstddef>
#include <cstdint>

#include "rig_fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sinew::fuzz::LoadedInput in;
  if (!sinew::fuzz::load_rig_input(data, size, &in)) return 0;
  static sinew::pipeline::Pipeline pipeline;
  for (const uint32_t tick_hz : {0u, sinew::fuzz::other_tick_hz(size)})
    (void)sinew::fuzz::start_pipeline(in, tick_hz, &pipeline);
  return 0;
}
