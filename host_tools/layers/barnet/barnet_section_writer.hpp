// The barnet layer's section (sim_core/barnet/barnet_section.hpp) from the builder's model.
#pragma once

#include <cstdint>
#include <span>

#include "host_tools/layers/sections/layer_section.hpp"
#include "sim_core/barnet/barnet_section.hpp"

namespace sinew::layers {

LayerSection barnet_section(const ::sinew::barnet::BarnetModel& model);

}  // namespace sinew::layers
