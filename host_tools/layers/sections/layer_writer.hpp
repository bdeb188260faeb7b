// Appends layer sections (rig format 1.1, sim_core/pipeline/layer_format.hpp)
// to a compiled rig blob, and writes the pipeline's own section, the external
// inputs; each layer writes its sections beside its builder
// (host_tools/layers/<layer>/*_section_writer.hpp). The only path from a
// builder to the board: the blob it returns has been loaded back by sim_core's
// own loader.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "host_tools/layers/sections/layer_section.hpp"
#include "sim_core/pipeline/layer_format.hpp"

namespace sinew::layers {

LayerSection external_inputs_section(std::span<const pipeline::ExternalInputRecord> inputs);

// Rebuilds `blob` (a core 1.0 blob from compile_rig) with the sections
// appended, version 1.1, a new CRC; then loads it with rig_init and
// layers_init. Returns false with the loader's message if it refuses.
bool append_layer_sections(std::vector<uint8_t>* blob, const std::vector<LayerSection>& sections, std::string* error);

}  // namespace sinew::layers
