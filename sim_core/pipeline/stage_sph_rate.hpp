// The SPH stage's conversion of a joint's gains to the loop's rate, used at
// init and by tools that show the converted model.
#pragma once

#include <cstdint>

#include "pipeline.hpp"
#include "sim_core/sph/sph_model.hpp"

namespace sinew::pipeline {

// The SPH gains of a joint compiled for compiled_hz, converted for tick_hz:
// substeps max(2, ceil(200 / tick_hz)) (dt <= 5 ms, as rigc picks them);
// with rho = dt_new / dt_compiled = (compiled_hz x s_compiled) /
// (tick_hz x s_new) as the exact fraction N / D, the gains scale as their
// definitions in docs/sph.md do: k_e dt^2, k_p dt^2 / h, the surface
// tension 6 sigma h dt^2 / (m C) and the load gain by rho^2 (two roundings
// of x N / D, half up; the load gain saturates at its Q2.30 limit, as
// rigc's builder saturates it), mu dt by rho, and the kept
// velocity 1 - c dt as 1 - (1 - damping) rho. The particles, h and the
// Tresca limit do not depend on the rate. Fails (kBadModel, naming the
// gain) when the rate needs more than 16 substeps or a gain leaves its range;
// for any u32 rates, a scaled gain beyond int64 saturates (then is refused,
// or for the load gain saturates at its Q2.30 limit) rather than overflowing.
PipelineStatus sph_gains_for_rate(const sph::SphParams& compiled, uint32_t compiled_hz, uint32_t tick_hz,
                                  sph::SphParams* out);

}  // namespace sinew::pipeline
