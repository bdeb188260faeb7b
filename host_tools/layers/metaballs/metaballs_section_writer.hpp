// The metaballs layer's section (sim_core/metaballs/metaballs_section.hpp) from the builder's model.
#pragma once

#include <cstdint>
#include <span>

#include "host_tools/layers/sections/layer_section.hpp"
#include "sim_core/metaballs/metaballs_section.hpp"

namespace sinew::layers {

LayerSection metaballs_section(const ::sinew::metaballs::MetaballModel& model);

}  // namespace sinew::layers
