// Validation of a bar-net model, without memory: counts against the limits,
// every index, every value range, and the structure eq. (4) needs (free
// nodes first, at least one fixed node). barnet_init adds the checks that
// need scratch memory (bars per node, a path from every free node to a fixed
// node, the factor's profile and pivots).
#pragma once

#include "barnet_model.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::barnet {

// Number of free nodes: nodes [0, free_count) are free, the rest fixed.
uint32_t free_count(const BarnetModel& model);

// The layer's safety contract: the checks above, and the joint, input and
// vertex counts against the rig the net runs on (the external-input count is
// the layer set's, checked by its loader).
LayerStatus barnet_validate(const BarnetModel& model, const rig::Rig& rig);

// The same checks without a rig: what barnet_state_bytes and barnet_init can
// verify of a model on its own.
LayerStatus barnet_validate_model(const BarnetModel& model);

}  // namespace sinew::barnet
