// Validation of a bar-net model, without memory: counts against the limits,
// every index, every value range, and the structure eq. (4) needs (free
// nodes first, at least one fixed node). barnet_init adds the checks that
// need scratch memory (bars per node, a path from every free node to a fixed
// node, the factor's profile and pivots).
#pragma once

#include "barnet_model.hpp"

namespace sinew::barnet {

// Number of free nodes: nodes [0, free_count) are free, the rest fixed.
uint32_t free_count(const BarnetModel& model);

LayerStatus barnet_validate(const BarnetModel& model);

}  // namespace sinew::barnet
