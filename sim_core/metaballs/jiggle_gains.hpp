// Jiggle gains in physical units (metaballs-pbd-skinning, "Secondary
// deformation"): the paper's time window W_t and the swing frequency become
// the per-step spring stiffness k and the kept velocity d of the PBD jiggle
// integrator (pbd.cpp) for one tick rate, so the motion is the same at any
// rate. Integer only (used by the offline builder and at run time alike).
//
// The integrator's error e = x - target about a still target follows
//   e_{n+1} = (1 - k) ((1 + d) e_n - d e_{n-1}),
// whose roots r exp(+-i theta) give the continuous swing
// e(t) = A exp(-sigma t) cos(omega t + phi) at every tick, exactly, when
//   r = exp(-sigma dt), theta = omega dt = 2 pi f dt,
//   1 - k = 2 r cos(theta) - r^2,   d = r^2 / (1 - k).
// W_t is the time in which the swing's envelope falls to kJiggleCriterion
// of its value (5 %, the usual settling band; the paper names no number):
//   sigma = ln(1 / kJiggleCriterion) / W_t.
#pragma once

#include <cstdint>

#include "sim_core/fixed/q_formats.hpp"

namespace sinew::metaballs {

// Envelope left after the time window W_t: 1/20, Q2.30.
inline constexpr fx::Unit kJiggleCriterion = fx::kUnitOne / 20;

struct JiggleGains {
  fx::Unit stiffness = 0;  // k, (0, 1], Q2.30: the model's ball_jiggle
  fx::Unit damping = 0;    // d, [0, 1), Q2.30: the model's jiggle_damping
};

// frequency_q16: the swing frequency f, Hz, Q16.16, > 0.
// window_q16: W_t, seconds, Q16.16, > 0.
// tick_hz: the step rate, > 0.
// Returns false (and leaves *out alone) when the rate cannot represent the
// swing: theta = 2 pi f / tick_hz must be below a quarter turn and the decay
// per tick r below cos(theta) (else d >= 1), i.e. roughly
// tick_hz > 4 f and tick_hz > 3 / (W_t (1 - cos theta)).
bool jiggle_gains(int32_t frequency_q16, int32_t window_q16, uint32_t tick_hz, JiggleGains* out);

// The gains `built` (made by jiggle_gains for built_hz) converted to
// tick_hz: the same sigma and omega, recovered from the gains' roots
// (r^2 = (1 - k) d, 2 r cos(theta) = (1 - k) (1 + d); sigma dt = -ln r by an
// atanh series, theta by fx::atan2_angle), scaled by built_hz / tick_hz and
// turned back into gains. Integer only, so every platform converts alike;
// the same rate returns `built` unchanged. The Q2.30 gains carry theta to
// within about 2^-30 / (theta sin theta) relative (a few 1e-6 at 4 Hz and
// 1 kHz), which sets the converted swing's phase drift. Returns false (and
// leaves *out alone) for gains no jiggle_gains could give or a rate that
// cannot carry the swing (as jiggle_gains).
bool jiggle_gains_for_rate(JiggleGains built, uint32_t built_hz, uint32_t tick_hz, JiggleGains* out);

// exp(-x) for x in Q2.30, x >= 0, result Q2.30 (within a few LSB).
fx::Unit exp_neg_unit(int64_t x_q30);

}  // namespace sinew::metaballs
