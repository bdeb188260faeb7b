// One elastic relaxation round (anatomically-based-modeling §5.2), Jacobi
// style: every force is computed from the positions at the start of the
// round, then every vertex moves by its relaxation vector
//   r(v) = ( sum_j k'_e (|w_j| - rest_j) w_j / |w_j|  + k_a (anchor - v)
//            + sum_bands k_r (target - v) ) / ( sum_j k'_e + k_a + sum k_r )
// with w_j = v_j - v, k_e from eq. (1), k_a from eq. (2) and k'_e the
// push-back-scaled stiffness for compressed edges. Edges are visited in
// model order and each vertex sums its terms in a fixed order (its edges in
// edge order, its bands in band order, its anchor): deterministic.
// Work: O(edges + bands + vertices).
#pragma once

#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/layer/workers.hpp"
#include "sim_core/muscle/muscle_state.hpp"
#include "skin_state.hpp"

namespace sinew::elastic_skin {

// The elastic pull of edge e on its endpoint a (towards b when stretched,
// the opposite on b): *k the push-back-scaled stiffness (Q16.16) and *f =
// excess * w / |w| (Len). False when the edge pulls with nothing.
bool edge_pull(const SkinParams& p, const Edge& e, const std::span<fx::Len> (&position)[3], int64_t* k, fx::Vec3* f);

// Runs one round over the moving edges and vertices (SkinState) and returns
// the largest relaxation vector length (Len).
// Two passes: each edge's pull once (over edges), then each vertex gathers
// its edges' pulls from the CSR (over vertices), so both spread over
// `workers` and the words written are the same for any number of them.
fx::Len relax_once(const SkinModel& model, const muscle::MuscleState& muscles, SkinState* s,
                   const layer::Workers* workers = nullptr);

// Edge stiffness after the push-back rule of §5.2 (Q16.16).
int64_t effective_stiffness(const SkinParams& p, Stiffness k, int64_t excess, fx::Len rest);

// An edge's spring at squared length n2 > 0 (Len^2): the stretch ratio
// (|w| - rest) / |w| = 1 - rest / |w| in Q2.30, 1 / |w| from the
// division-free reciprocal square root (relative error about 1e-9), and
// the push-back-scaled stiffness (Q16.16; 0: the edge pulls with nothing).
// Only a compressed edge, whose push-back multiplier needs the excess
// itself, takes the exact root. The static relaxation's and the dynamic
// integrator's springs both.
struct EdgeSpring {
  int64_t ratio;
  int64_t k;
};
[[gnu::always_inline]] inline EdgeSpring edge_spring(const SkinParams& p, const Edge& e, uint64_t n2) {
  const fx::RsqrtResult r = fx::rsqrt_fast(n2);                                       // 1/|w| = y 2^(half_shift - 61)
  const int shift = 31 - r.half_shift;                                                // 0..31
  const int64_t scaled = int64_t{e.rest} * r.y;                                       // rest < 2^31, y < 2^31
  const int64_t rest_over_len = shift > 0 ? fx::round_shift(scaled, shift) : scaled;  // Q2.30
  const int64_t ratio = fx::kUnitOne - rest_over_len;
  if (ratio >= 0) return {ratio, e.k};
  return {ratio, effective_stiffness(p, e.k, int64_t{fx::isqrt_fast(n2)} - e.rest, e.rest)};
}

// The centre of the collision sphere under each moving vertex's virtual
// anchor of this step (§5.2: radius R, R below the anchor along its
// normal), into s->sphere_centre: once a step, after the anchors are mapped.
void place_anchor_spheres(const SkinModel& model, SkinState* s, const layer::Workers* workers = nullptr);

// Moves each moving vertex out of its collision sphere (placed by
// place_anchor_spheres for this step's anchors); returns the number of
// vertices moved.
uint32_t collide_with_anchor_spheres(const SkinModel& model, SkinState* s, const layer::Workers* workers = nullptr);

}  // namespace sinew::elastic_skin
