// Validation of a MetaballModel: every count against the maxima, every index
// against its target, every weight sum, range and unit direction. A model that
// passes cannot make the step read out of bounds or overflow its bounded work.
#pragma once

#include "model.hpp"
#include "sim_core/rig/rig.hpp"
#include "status.hpp"

namespace sinew::metaballs {

// The layer's safety contract: the checks above, and the joint and vertex
// counts against the rig the model runs on.
LayerStatus metaballs_validate(const MetaballModel& model, const rig::Rig& rig);

// The same checks without a rig: what metaballs_state_bytes and
// metaballs_init can verify of a model on its own.
LayerStatus metaballs_validate_model(const MetaballModel& model);

}  // namespace sinew::metaballs
