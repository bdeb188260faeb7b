// The metaballs jobs report the layer status (sim_core/layer/layer_status.hpp):
// a code plus a message naming the offending field (and index), filled
// without heap or stdio.
#pragma once

#include "sim_core/layer/layer_status.hpp"

namespace sinew::metaballs {

using layer::LayerError;
using layer::LayerStatus;

}  // namespace sinew::metaballs
