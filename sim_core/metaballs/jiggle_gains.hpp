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

// The springs of eq. (3) between a jiggle ball and its neighbours, in
// physical units: unit-mass balls joined by springs of stiffness omega_c^2
// per unit mass. The spring's force -omega_c^2 C grad C, from the positions
// at the start of the tick, enters the swing's recurrence as the bone's
// acceleration does (pbd.cpp, swing_relative), scaled by h^2: that is
// x C with x = (omega_c h)^2. Taken from the start of the tick (Stoermer-
// Verlet) the spring adds no damping and its frequency error is second
// order in h; projecting the predicted positions instead, as PBD and XPBD
// do, would damp the coupled swing by 1 / sqrt(1 + x) every tick (40 % over
// 0.4 s at 250 Hz and 4 Hz, 12 % at 1 kHz), so the jiggle would depend on
// the rate. Stable while (omega h)^2 < 4 for every mode: pbd.cpp checks
// Gershgorin's bound, theta^2 + sum over a ball's pairs of 2 x < 4.

// x = (2 pi f / tick_hz)^2, Q2.30, for the coupling frequency f (Hz, Q16.16,
// > 0); 0 when f is not positive or x would exceed 1 (f > tick_hz / 2 pi).
fx::Unit coupling_stiffness(int32_t frequency_q16, uint32_t tick_hz);

// A coupling x made for built_hz at tick_hz: x (built_hz / tick_hz)^2,
// rounded. False (and *out left alone) for x outside (0, 1], a rate of 0,
// or a result of 2 or more.
bool coupling_for_rate(fx::Unit coupling, uint32_t built_hz, uint32_t tick_hz, fx::Unit* out);

// exp(-x) for x in Q2.30, x >= 0, result Q2.30 (within a few LSB).
fx::Unit exp_neg_unit(int64_t x_q30);

}  // namespace sinew::metaballs
