// Force densities that change at run time (barnet-driven-skinning, Fig. 3 (d):
// a lower force density gives a larger bulge): the per-bar q scaled by
// external inputs, and the assembly of D = C^T Q C (eq. (3)) into the skyline
// storage that ldlt_factor then factorises in place. Used once at init (the
// model's q) and, for a model with ForceDensityInputs, at every step.
//
// Work of a step's re-factorisation is fixed by the net's topology, not by
// the inputs' values: bars (scale and assembly) + refactor_products(factor)
// 64x64-bit products + n reciprocals. No branch depends on the values beyond
// clamps, so the cost is the same every step.
#pragma once

#include <cstdint>
#include <span>

#include "barnet_model.hpp"
#include "ldlt_skyline.hpp"

namespace sinew::barnet {

// q_out[b] = the model's q of bar b, scaled by every ForceDensityInput run
// holding b (scale = external value clamped to [2^-8, 2^8], product rounded
// once per run and clamped to [kMinForceDensity, kMaxForceDensity]).
// `external` may be shorter than external_count: missing inputs read as 1.
void scale_force_densities(const BarnetModel& model, std::span<const int32_t> external, std::span<ForceDensity> q_out,
                           fx::Saturation& sat);

// D's diagonal into factor.recip and its off-diagonal entries into
// factor.lower (Q16.16 q), for the skyline rows already set in `factor`.
void assemble_matrix(std::span<const BarRecord> bars, std::span<const ForceDensity> q, const SkylineFactor& factor);

// 64x64-bit products ldlt_factor performs for this skyline (the profile's
// inner products, then one division per entry of L): the fixed cost of a
// re-factorisation.
uint64_t refactor_products(const SkylineFactor& factor);

}  // namespace sinew::barnet
