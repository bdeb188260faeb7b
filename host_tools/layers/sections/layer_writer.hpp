// Writes the layer sections of the rig format 1.1 (sim_core/pipeline/
// layer_format.hpp) from the runtime models the offline builders produce, and
// appends them to a compiled rig blob. The only path from a builder to the
// board: the blob it returns has been loaded back by sim_core's own loader.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "sim_core/barnet/barnet_section.hpp"
#include "sim_core/elastic_skin/skin_section.hpp"
#include "sim_core/metaballs/metaballs_section.hpp"
#include "sim_core/muscle/muscle_section.hpp"
#include "sim_core/pipeline/layer_format.hpp"
#include "sim_core/sph/sph_section.hpp"

namespace sinew::layers {

inline constexpr uint32_t kNoBaseAcceleration[3] = {pipeline::kNoExternalInput, pipeline::kNoExternalInput,
                                                    pipeline::kNoExternalInput};

struct LayerSection {
  uint32_t id = 0;
  std::vector<uint8_t> payload;  // a multiple of 8 bytes
  // Not empty when the writer's arrays disagree with the section's
  // descriptor (a bug here, never the model's): names the section, version
  // and array; append_layer_sections refuses the section with it.
  std::string problem;
};

LayerSection sph_section(const ::sinew::sph::SphModel& model, uint32_t rate_hz, uint32_t force_input);
LayerSection metaballs_section(const ::sinew::metaballs::MetaballModel& model);
LayerSection muscles_section(const ::sinew::muscle::MuscleModel& model);
// base_acceleration: the EXTI indices of the base's acceleration x, y, z
// (pipeline::kNoExternalInput: none); any set makes it a version 5 section.
LayerSection skin_section(const ::sinew::elastic_skin::SkinModel& model, std::span<const uint32_t> region = {},
                          std::span<const fx::Unit> region_weight = {},
                          const uint32_t (&base_acceleration)[3] = kNoBaseAcceleration);
LayerSection barnet_section(const ::sinew::barnet::BarnetModel& model);
LayerSection external_inputs_section(std::span<const pipeline::ExternalInputRecord> inputs);

// Rebuilds `blob` (a core 1.0 blob from compile_rig) with the sections
// appended, version 1.1, a new CRC; then loads it with rig_init and
// layers_init. Returns false with the loader's message if it refuses.
bool append_layer_sections(std::vector<uint8_t>* blob, const std::vector<LayerSection>& sections, std::string* error);

}  // namespace sinew::layers
