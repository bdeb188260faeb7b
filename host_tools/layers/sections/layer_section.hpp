// A layer section ready to append to a compiled rig blob: its id and its
// payload as the section's descriptor lays it out (section_builder.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace sinew::layers {

struct LayerSection {
  uint32_t id = 0;
  std::vector<uint8_t> payload;  // a multiple of 8 bytes
  // Not empty when the writer's arrays disagree with the section's
  // descriptor (a bug here, never the model's): names the section, version
  // and array; append_layer_sections refuses the section with it.
  std::string problem;
};

}  // namespace sinew::layers
