// Validation of a MetaballModel: every count against the maxima, every index
// against its target, every weight sum, range and unit direction. A model that
// passes cannot make the step read out of bounds or overflow its bounded work.
#pragma once

#include "model.hpp"
#include "status.hpp"

namespace sinew::metaballs {

LayerStatus metaballs_validate(const MetaballModel& model);

}  // namespace sinew::metaballs
