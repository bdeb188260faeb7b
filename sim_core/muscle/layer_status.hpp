// The anatomy layers (muscles, elastic skin) report the layer status
// (sim_core/layer/layer_status.hpp): an error code and a message naming the
// offending record and field.
#pragma once

#include "sim_core/layer/layer_status.hpp"

namespace sinew::muscle {

using layer::layer_fail;
using layer::LayerError;
using layer::LayerStatus;

}  // namespace sinew::muscle
