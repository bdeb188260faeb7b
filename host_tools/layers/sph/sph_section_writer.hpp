// The sph layer's section (sim_core/sph/sph_section.hpp) from the builder's model.
#pragma once

#include <cstdint>
#include <span>

#include "host_tools/layers/sections/layer_section.hpp"
#include "sim_core/sph/sph_section.hpp"

namespace sinew::layers {

LayerSection sph_section(const ::sinew::sph::SphModel& model, uint32_t rate_hz, uint32_t force_input);

}  // namespace sinew::layers
