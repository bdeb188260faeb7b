// LEMAN's elastic surface advanced by §6.11's relaxation (dynamic mode,
// SkinIntegrator::kRelaxation).
//
// One backward-Euler step of h = 1 / tick_hz per tick. The unknowns are the
// end positions x; with x0, v0 the start state, x~ = x0 + h v0 the inertial
// prediction and a the virtual anchors at the step's end, vertex i's
// equation of motion times h^2 / m reads r_i(x) = 0 with
//
//   r_i = (x~_i - x_i)                                         inertia
//       + h^2/m k_a (a_i - x_i) + h/m c_a ((a_i - a0_i) - (x_i - x0_i))     anchor spring + dashpot
//       + sum_edges h^2/m k_e' (1 - L/|d|) d,  d = x_j - x_i         stretch (§3; eq. 1, §5.2 push-back)
//       + h/m c_e ((x_j - x0_j) - (x_i - x0_i)) . e e               edge dashpot
//       + h^2/m k_b (u_i - sum_{j in N(i)} u_j / n_j)                  bend, u = L(x - a)
//       + sum_bands h^2/m k_r (t - x_i) + h/m c_r ((t - t0) - (x_i - x0_i))   rubber bands (§5.5)
//       + h^2 (g - a_base) + h^2/m P A_i n_i                         gravity, frame, air pressure (§5.3)
//
// (L the umbrella operator: (L y)_i = mean of y over i's edge neighbours -
// y_i; the bend term is -grad of 1/2 k_b sum |L(x - a)|^2, so the skin keeps
// the curvature its anchors carry; A_i n_i a third of the area vectors of
// i's faces, from x0.) §6.11: "a simple Gauss-Seidel or relaxation
// technique ... only a few relaxation iterations are performed at each time
// step, typically two to four ... the resulting error manifests itself as
// damping". Each sweep visits the vertices in index order and moves each by
// r_i / D_i, D_i the diagonal of the system (1 + h c/m + h^2 k/m summed
// over its terms, the bend's k_b (1 + sum 1/n_j^2)); the umbrella vectors
// follow every move, so the sweep is Gauss-Seidel for the bend too.
// Backward Euler with a diagonally dominant system: stable at any h (the
// tests run the arm's stiffest skin at 100 Hz, h omega_max = 8).
//
// Reaction constraints (§3, Platt-Barr): once per step (§6.11: the mesh is
// inside-tested, the gradients passed on) each fat point at x~ is pushed out
// of the active primitives; a point inside by e0 (the push-out's length),
// n the unit gradient at the point of the first primitive it is inside
// (§6.11's constraint gradient: a direction taken from a move of a few LSB
// would be off by tens of degrees), gets a floor on
// its normal coordinate: its penetration follows the critically damped law
// e'' + 2 w e' + w^2 e = 0 (w = 2 pi reaction_frequency), discretised by
// backward Euler over the step from e(x0) = e0 + h w_n, e'(x0) = -w_n (w_n
// the vertex's outward speed relative to its anchor), so
//   h e'_end = -(h w_n + (w h)^2 (e0 + h w_n)) / (1 + w h)^2,
//   floor = n . x~ + e0 - e_end,  e_end = e0 + h w_n + h e'_end.
// A sweep that leaves n . x_i below the floor lifts it there along n alone:
// the force along the normal is replaced, the tangential one is not, and the
// skin slides. w h -> inf is the projection onto the surface, w h -> 0 no
// reaction; the response never overshoots (backward Euler of a critically
// damped system is overdamped).
//
// Fixed point: positions and displacements Q28.36 (as the explicit
// integrator), gains h^2 k / m and h c / m Q30 (unbounded above: the
// implicit step admits any), 1 / D Q30, the umbrella vectors Q28.36,
// reaction normals Q2.30. Work per tick: edges + faces (pressure) +
// candidates * primitives * newton_steps + iterations * (2 edges + bands +
// vertices); no allocation.
#pragma once

#include "dynamic_math.hpp"
#include "sim_core/muscle/muscle_state.hpp"
#include "skin_state.hpp"

namespace sinew::elastic_skin {

// On entry: s->fine and s->position the start positions x0, s->velocity the
// predicted displacement h v0 (Q28.36), s->anchor_start / s->anchor and
// s->band_start / s->band_end the anchors and band targets at the step's
// start and end, s->normal the end anchors' normals; g the gains for
// h = 1 / tick_hz (one substep). On return: s->fine, s->position the end
// positions, s->velocity = x - x0, s->stats.reactions the vertices with a
// reaction floor; returns the reaction candidates' count (listed in
// s->weight for count_inside_of).
uint32_t relaxation_step(const SkinModel& model, const muscle::MuscleState& muscles, const dynamic::Gains& g,
                         uint32_t tick_hz, SkinState* s);

}  // namespace sinew::elastic_skin
