#include "surface_relaxation.hpp"

#include <algorithm>
#include <bit>

#include "reaction.hpp"
#include "sim_core/fixed/scalar.hpp"
#include "sim_core/fixed/vec3.hpp"
#include "surface_normals.hpp"

namespace sinew::elastic_skin {
namespace {

using namespace dynamic;  // NOLINT(google-build-using-namespace): the integrators' shared arithmetic

constexpr int64_t kOne = int64_t{1} << kGainFracBits;
constexpr int64_t kTwoPiQ29 = 3373259426;     // 2 pi, Q29
constexpr int64_t kMaxReactionOmegaH = 4096;  // w h beyond this is the projection to within 2^-24 of e0
constexpr int kAreaShift = 2;                 // Len differences -> |e| <= 2^30, as surface_normals.cpp

int64_t fine_of(fx::Len x) { return int64_t{x} * (int64_t{1} << kFineExtraBits); }

// a . b for a Q2.30 direction and a Q28.36 vector: Q28.36.
int64_t dot_unit(const int64_t n[3], const int64_t x[3]) {
  int64_t sum = 0;
  for (int c = 0; c < 3; ++c) sum = fx::add_sat_i64(sum, fx::mul_shift_round(n[c], x[c], fx::kUnitFracBits));
  return sum;
}

// The step's gains beyond the explicit integrator's (h = 1 / tick_hz).
struct SurfaceGains {
  int64_t bend = 0;            // h^2 k_b / m, Q30
  int64_t pressure = 0;        // h^2 P / (6 m), Q30 per rig unit (times twice a face's area vector)
  int64_t omega_h = 0;         // w h of the reaction, Q30 (capped)
  int64_t inverse_damped = 0;  // 1 / (1 + w h)^2, Q30
};

SurfaceGains surface_gains(const SkinModel& model, const Gains& g, uint32_t tick_hz) {
  const SkinSurfaceParams& p = model.surface;
  const SkinSolverParams& sp = model.solver;
  SurfaceGains out;
  out.bend = mul_shift_sat(p.bend, g.spring_h2, kStiffnessFracBits + kSpringFracBits - kGainFracBits);
  if (p.pressure != 0) {
    // P / m, Q16.16 (1 / (rig unit s^2)), then / 6 and h^2 in two steps of 2^7.
    const int64_t per_mass =
        fx::div_round(int64_t{p.pressure < 0 ? -p.pressure : p.pressure} << kMassFracBits, int64_t{sp.vertex_mass} * 6);
    const int64_t magnitude = per_substep(per_substep(per_mass, 7, tick_hz), 7, tick_hz);
    out.pressure = p.pressure < 0 ? -magnitude : magnitude;
  }
  // w h = 2 pi f / tick_hz: Q16.16 x Q29 -> Q30 needs a shift of 15.
  const int64_t omega = mul_shift_sat(p.reaction_frequency, kTwoPiQ29, 15);  // rad/s, Q30
  out.omega_h = std::min(fx::div_round(omega, tick_hz), kMaxReactionOmegaH << kGainFracBits);
  const int64_t one_plus = kOne + out.omega_h;  // <= 2^42.1
  const int64_t squared = mul_shift_sat(one_plus, one_plus, kGainFracBits);
  out.inverse_damped = fx::div_round(int64_t{1} << 60, squared);
  return out;
}

// Twice the area vectors of each vertex's faces (sum over its faces of
// (p_b - p_a) x (p_c - p_a), each face turned to the side of its corners'
// anchor normals), in Len^2 / 2^4, into out (int64, saturated).
void area_vectors(const SkinModel& model, const SkinState& s, std::span<int64_t> (&out)[3]) {
  for (int c = 0; c < 3; ++c)
    for (uint32_t v = 0; v < model.vertex_count; ++v) out[c][v] = 0;
  const size_t faces = model.triangles.size() / 3;
  for (size_t f = 0; f < faces; ++f) {
    const uint32_t at[3] = {model.triangles[3 * f], model.triangles[3 * f + 1], model.triangles[3 * f + 2]};
    int64_t e1[3], e2[3], side = 0;
    for (int c = 0; c < 3; ++c) {
      const int64_t a = s.position[c][at[0]];
      e1[c] = (s.position[c][at[1]] - a) >> kAreaShift;
      e2[c] = (s.position[c][at[2]] - a) >> kAreaShift;
    }
    int64_t cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    // The side only: the cross narrowed to 30 significant bits, the
    // corners' normals summed and halved (|each| < 2^31), so each product <
    // 2^61 and their sum fits.
    const int shift = std::max(0, static_cast<int>(std::bit_width(std::max(
                                      {fx::magnitude(cross[0]), fx::magnitude(cross[1]), fx::magnitude(cross[2])}))) -
                                      30);
    for (int c = 0; c < 3; ++c) {
      const int64_t normal = (int64_t{s.normal[c][at[0]]} + s.normal[c][at[1]] + s.normal[c][at[2]]) >> 1;
      side += (cross[c] >> shift) * normal;
    }
    if (side < 0)
      for (int64_t& x : cross) x = -x;
    for (int c = 0; c < 3; ++c)
      for (uint32_t v : at) out[c][v] = fx::add_sat_i64(out[c][v], cross[c]);
  }
}

// Vertex v's edge terms of r_v at the present positions: the springs (eq. 1
// with the push-back rule) and, with edge dashpots, their dampers.
void add_edge_terms(const SkinModel& model, const Gains& g, uint32_t v, const SkinState& s, int64_t r[3]) {
  for (uint32_t k = s.incident_offset[v]; k < s.incident_offset[v + 1]; ++k) {
    const uint32_t edge = s.incident_edge[k];
    int64_t pull[3];
    if (edge_displacement(model.params, model.edges[edge], g.spring_h2, s.edge_gain[edge], s.position, pull)) {
      const bool at_a = s.incident_at_b[k] == 0;
      for (int c = 0; c < 3; ++c) r[c] = fx::add_sat_i64(r[c], at_a ? pull[c] : -pull[c]);
    }
    if (g.edge_gamma == 0) continue;
    const uint32_t j = s.incident_neighbour[k];
    const fx::Vec3 w{fx::sub_sat(s.position[0][j], s.position[0][v]), fx::sub_sat(s.position[1][j], s.position[1][v]),
                     fx::sub_sat(s.position[2][j], s.position[2][v])};
    fx::Vec3 dir{};
    if (!fx::normalize_to_unit(w, &dir)) continue;
    const int64_t u[3] = {dir.x, dir.y, dir.z};
    int64_t relative[3];
    for (int c = 0; c < 3; ++c) relative[c] = (s.fine[c][j] - s.step_start[c][j]) - (s.fine[c][v] - s.step_start[c][v]);
    const int64_t along = mul_shift_sat(g.edge_gamma, dot_unit(u, relative), kGainFracBits);
    for (int c = 0; c < 3; ++c) r[c] = fx::add_sat_i64(r[c], fx::mul_shift_round(along, u[c], fx::kUnitFracBits));
  }
}

// u = L(x - a) from the present positions, exactly.
void umbrella_vectors(const SkinModel& model, SkinState* s) {
  for (uint32_t v = 0; v < model.vertex_count; ++v) {
    for (int c = 0; c < 3; ++c) {
      int64_t sum = 0;
      for (uint32_t k = s->incident_offset[v]; k < s->incident_offset[v + 1]; ++k) {
        const uint32_t j = s->incident_neighbour[k];
        sum = fx::add_sat_i64(sum, s->fine[c][j] - fine_of(s->anchor[c][j]));
      }
      const int64_t mean = mul_shift_sat(sum, s->inverse_degree[v], fx::kUnitFracBits);
      s->bend[c][v] = s->inverse_degree[v] == 0 ? 0 : mean - (s->fine[c][v] - fine_of(s->anchor[c][v]));
    }
  }
}

// The Platt-Barr floor of each reaction candidate (surface_relaxation.hpp),
// from the gradients and depths reaction_moves leaves in s->reaction_normal
// and s->reaction_floor.
uint32_t reaction_floors(const SkinModel& model, const muscle::MuscleState& muscles, const SurfaceGains& sg,
                         SkinState* s) {
  for (int c = 0; c < 3; ++c)
    for (uint32_t v = 0; v < model.vertex_count; ++v) s->reaction_normal[c][v] = 0;
  for (uint32_t v = 0; v < model.vertex_count; ++v) s->reaction_floor[v] = 0;
  if (muscles.primitives.empty()) return 0;
  estimate_surface_normals(model, s);  // kSurface only: the fat along the predicted skin's normal (§5.6)
  const uint32_t candidates = list_reaction_candidates(model, muscles, s);
  const uint32_t active = reaction_moves(model, muscles, candidates, s);
  const int64_t omega2 = mul_shift_sat(sg.omega_h, sg.omega_h, kGainFracBits);
  for (uint32_t k = 0; k < candidates; ++k) {
    const uint32_t v = static_cast<uint32_t>(s->weight[k]);
    const int64_t n[3] = {s->reaction_normal[0][v], s->reaction_normal[1][v], s->reaction_normal[2][v]};
    if (n[0] == 0 && n[1] == 0 && n[2] == 0) continue;
    const int64_t depth = s->reaction_floor[v];
    // h w_n: the predicted move relative to the anchor, along n.
    int64_t relative[3], predicted[3];
    for (int c = 0; c < 3; ++c) {
      predicted[c] = s->fine[c][v];
      relative[c] = s->velocity[c][v] - (fine_of(s->anchor[c][v]) - fine_of(s->anchor_start[c][v]));
    }
    const int64_t hw = dot_unit(n, relative);
    const int64_t e_start = fx::add_sat_i64(depth, hw);
    const int64_t h_rate = -mul_shift_sat(fx::add_sat_i64(hw, mul_shift_sat(omega2, e_start, kGainFracBits)),
                                          sg.inverse_damped, kGainFracBits);
    const int64_t e_end = fx::add_sat_i64(e_start, h_rate);
    s->reaction_floor[v] = fx::add_sat_i64(dot_unit(n, predicted), depth - e_end);
  }
  s->stats.reactions = active;
  return candidates;
}

void set_position(uint32_t v, SkinState* s) {
  for (int c = 0; c < 3; ++c) s->position[c][v] = fx::sat_i32(fx::round_shift(s->fine[c][v], kFineExtraBits));
}

}  // namespace

uint32_t relaxation_step(const SkinModel& model, const muscle::MuscleState& muscles, const Gains& g, uint32_t tick_hz,
                         SkinState* s) {
  const uint32_t count = model.vertex_count;
  const SurfaceGains sg = surface_gains(model, g, tick_hz);
  // Explicit terms, from x0 and the anchors' and targets' motion, into
  // s->force (Q28.36): the field, the air pressure, and the constants of
  // the terms linear in x_i (below).
  if (sg.pressure != 0) area_vectors(model, *s, s->bend);
  for (uint32_t v = 0; v < count; ++v) {
    s->linear_gain[v] = kOne + g.anchor_gamma;  // inertia and the anchor dashpot
    for (int c = 0; c < 3; ++c) {
      s->step_start[c][v] = s->fine[c][v];
      int64_t f = g.external[c];
      if (sg.pressure != 0) f = fx::add_sat_i64(f, mul_shift_sat(sg.pressure, s->bend[c][v], kGainFracBits));
      s->force[c][v] = f;
    }
  }
  // Terms linear in x_i alone, K x_i - B: inertia (x~ - x), the anchor
  // spring and dashpot, the bands' springs and dashpots. They are kept
  // relative to the prediction x~ (y = x - x~): the constants B - K x~
  // stay small, and so do their products.
  for (uint32_t v = 0; v < count; ++v) {
    const int64_t kappa =
        mul_shift_sat(model.anchor_stiffness[v], g.spring_h2, kStiffnessFracBits + kSpringFracBits - kGainFracBits);
    s->linear_gain[v] += kappa;
    for (int c = 0; c < 3; ++c) {
      const int64_t predicted = clamp_displacement(s->velocity[c][v]);  // x~ - x0
      const int64_t anchor_move = fine_of(s->anchor[c][v]) - fine_of(s->anchor_start[c][v]);
      // kappa (a - x~) + gamma ((a - a0) - (x~ - x0)).
      const int64_t to_anchor = fine_of(s->anchor[c][v]) - (s->fine[c][v] + predicted);
      int64_t f = fx::add_sat_i64(s->force[c][v], mul_shift_sat(kappa, to_anchor, kGainFracBits));
      f = fx::add_sat_i64(f, mul_shift_sat(g.anchor_gamma, anchor_move - predicted, kGainFracBits));
      s->force[c][v] = f;
      // The start's numerator (below): the anchor's pull changed by the step.
      s->bend[c][v] = mul_shift_sat(kappa + g.anchor_gamma, anchor_move - predicted, kGainFracBits);
    }
  }
  for (size_t i = 0; i < model.bands.size(); ++i) {
    const RubberBand& b = model.bands[i];
    const int64_t kappa = mul_shift_sat(b.k, g.spring_h2, kStiffnessFracBits + kSpringFracBits - kGainFracBits);
    s->linear_gain[b.vertex] = fx::add_sat_i64(s->linear_gain[b.vertex], kappa + g.band_gamma);
    for (int c = 0; c < 3; ++c) {
      const int64_t predicted = clamp_displacement(s->velocity[c][b.vertex]);
      const int64_t target = fine_of(s->band_end[c][i]);
      const int64_t to_target = target - (s->fine[c][b.vertex] + predicted);
      const int64_t target_move = target - fine_of(s->band_start[c][i]);
      int64_t f = fx::add_sat_i64(s->force[c][b.vertex], mul_shift_sat(kappa, to_target, kGainFracBits));
      f = fx::add_sat_i64(f, mul_shift_sat(g.band_gamma, target_move - predicted, kGainFracBits));
      s->force[c][b.vertex] = f;
      s->bend[c][b.vertex] = fx::add_sat_i64(
          s->bend[c][b.vertex], mul_shift_sat(kappa + g.band_gamma, target_move - predicted, kGainFracBits));
    }
  }
  // The prediction x~ = x0 + h v0 starts the sweeps.
  for (uint32_t v = 0; v < count; ++v) {
    for (int c = 0; c < 3; ++c)
      s->fine[c][v] = fx::clamp_i64(s->fine[c][v] + clamp_displacement(s->velocity[c][v]), kFineMin, kFineMax);
    set_position(v, s);
  }
  const uint32_t candidates = reaction_floors(model, muscles, sg, s);
  // The sweeps start from each vertex's own terms solved for the step's
  // change: K (x - x~) = (k + c)(anchor move - predicted move), summed over
  // the anchor and the bands (h^2 / m units). The last step left the skin
  // balanced, so only what changed pulls; at rest this is x~ itself, and a
  // motion of the whole skin, which leaves its edges as they were, is
  // solved before the first sweep. Gauss-Seidel, quick on the membrane's
  // short waves, is slow on such long ones: from x~ alone the arm's
  // forearm skin, stopped at 100 Hz, followed through 4x further than its
  // anchors allow.
  for (uint32_t v = 0; v < count; ++v) {
    const int64_t inverse = fx::div_round(int64_t{1} << 60, s->linear_gain[v]);  // 1 / K, Q30 (K >= 1)
    for (int c = 0; c < 3; ++c) {
      const int64_t local = clamp_displacement(mul_shift_sat(s->bend[c][v], inverse, kGainFracBits));
      s->fine[c][v] = fx::clamp_i64(s->fine[c][v] + local, kFineMin, kFineMax);
    }
    set_position(v, s);
  }
  // Each edge's spring gain of the step, then the diagonal of each row:
  // K + sum over edges (k_e + c_e) + bend.
  for (size_t e = 0; e < model.edges.size(); ++e) s->edge_gain[e] = spring_gain(model.edges[e].k, g.spring_h2);
  for (uint32_t v = 0; v < count; ++v) {
    int64_t d = s->linear_gain[v];
    int64_t bend_diagonal = kOne;  // 1 + sum_j 1 / n_j^2, Q30
    for (uint32_t k = s->incident_offset[v]; k < s->incident_offset[v + 1]; ++k) {
      const int64_t inverse_j = s->neighbour_inverse_degree[k];
      d = fx::add_sat_i64(d, s->edge_gain[s->incident_edge[k]]);
      d = fx::add_sat_i64(d, g.edge_gamma);
      bend_diagonal += fx::mul_shift_round(inverse_j, inverse_j, fx::kUnitFracBits);
    }
    if (s->incident_offset[v + 1] > s->incident_offset[v])
      d = fx::add_sat_i64(d, mul_shift_sat(sg.bend, bend_diagonal, kGainFracBits));
    s->inverse_diagonal[v] = fx::div_round(int64_t{1} << 60, d);  // d >= 1 (Q30): the inverse <= 1
  }
  const bool bend = sg.bend != 0;
  if (bend) umbrella_vectors(model, s);
  const uint32_t sweeps = std::clamp<uint32_t>(model.surface.relaxation_iterations, 1, kMaxRelaxationIterations);
  uint64_t largest = 0;
  for (uint32_t sweep = 0; sweep < sweeps; ++sweep) {
    largest = 0;
    for (uint32_t v = 0; v < count; ++v) {
      const uint32_t first = s->incident_offset[v], last = s->incident_offset[v + 1];
      int64_t r[3];
      for (int c = 0; c < 3; ++c) {
        const int64_t offset = s->fine[c][v] - s->step_start[c][v] - clamp_displacement(s->velocity[c][v]);  // x - x~
        r[c] = fx::add_sat_i64(s->force[c][v], -mul_shift_sat(s->linear_gain[v], offset, kGainFracBits));
      }
      add_edge_terms(model, g, v, *s, r);
      if (bend) {
        // sum_j u_j / n_j, each component in slot order.
        int64_t spread[3] = {0, 0, 0};
        for (uint32_t k = first; k < last; ++k) {
          const uint32_t j = s->incident_neighbour[k];
          const int64_t inverse_j = s->neighbour_inverse_degree[k];
          for (int c = 0; c < 3; ++c)
            spread[c] = fx::add_sat_i64(spread[c], fx::mul_shift_round(s->bend[c][j], inverse_j, fx::kUnitFracBits));
        }
        for (int c = 0; c < 3; ++c)
          r[c] = fx::add_sat_i64(r[c], mul_shift_sat(sg.bend, s->bend[c][v] - spread[c], kGainFracBits));
      }
      int64_t move[3];
      for (int c = 0; c < 3; ++c) {
        move[c] = clamp_displacement(mul_shift_sat(r[c], s->inverse_diagonal[v], kGainFracBits));
        s->fine[c][v] = fx::clamp_i64(s->fine[c][v] + move[c], kFineMin, kFineMax);
      }
      // Platt-Barr: the normal coordinate no lower than the floor, the
      // tangential motion as the forces left it.
      if (s->reaction_normal[0][v] != 0 || s->reaction_normal[1][v] != 0 || s->reaction_normal[2][v] != 0) {
        const int64_t n[3] = {s->reaction_normal[0][v], s->reaction_normal[1][v], s->reaction_normal[2][v]};
        const int64_t x[3] = {s->fine[0][v], s->fine[1][v], s->fine[2][v]};
        const int64_t lift = s->reaction_floor[v] - dot_unit(n, x);
        if (lift > 0)
          for (int c = 0; c < 3; ++c) {
            const int64_t up = fx::mul_shift_round(lift, n[c], fx::kUnitFracBits);
            s->fine[c][v] = fx::clamp_i64(s->fine[c][v] + up, kFineMin, kFineMax);
            move[c] += up;
          }
      }
      set_position(v, s);
      // The umbrella vectors follow the move: u_v -= m, u_j += m / n_j.
      if (bend) {
        for (int c = 0; c < 3; ++c) s->bend[c][v] -= move[c];
        for (uint32_t k = first; k < last; ++k) {
          const uint32_t j = s->incident_neighbour[k];
          const int64_t inverse_j = s->neighbour_inverse_degree[k];
          for (int c = 0; c < 3; ++c) s->bend[c][j] += fx::mul_shift_round(move[c], inverse_j, fx::kUnitFracBits);
        }
      }
      uint64_t m2 = 0;
      for (int c = 0; c < 3; ++c) {
        const uint64_t m = std::min<uint64_t>(fx::magnitude(move[c]) >> kFineExtraBits, INT32_MAX);
        m2 += m * m;
      }
      largest = std::max(largest, m2);
    }
  }
  for (int c = 0; c < 3; ++c)
    for (uint32_t v = 0; v < count; ++v) s->velocity[c][v] = s->fine[c][v] - s->step_start[c][v];
  s->stats.iterations = sweeps;
  s->stats.max_relax_last = fx::sat_i32(int64_t{fx::isqrt_fast(largest)});
  return candidates;
}

}  // namespace sinew::elastic_skin
