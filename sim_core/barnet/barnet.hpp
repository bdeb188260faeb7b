// The bar-net layer (barnet-driven-skinning): one include for its API.
//   barnet_validate   model checks that need no memory
//   barnet_state_bytes / barnet_init   state from caller memory, D factorised
//   barnet_step       bones + joint angles -> node and wrapped skin positions
// docs/barnet.md describes the model, the numerics and the engine's call sequence.
#pragma once

#include "barnet_model.hpp"
#include "barnet_state.hpp"
#include "barnet_step.hpp"
#include "barnet_validate.hpp"
