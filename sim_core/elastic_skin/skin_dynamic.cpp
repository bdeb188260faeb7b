#include "skin_dynamic.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>

#include "dynamic_math.hpp"
#include "invariant_division.hpp"
#include "reaction.hpp"
#include "relaxation.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/wide.hpp"
#include "surface_normals.hpp"
#include "surface_relaxation.hpp"
#include "virtual_anchors.hpp"

namespace sinew::elastic_skin {
namespace {

using namespace dynamic;  // NOLINT(google-build-using-namespace): the integrators' shared arithmetic

// start + (end - start) * j / n, rounded: the linear path across a tick
// (by_n: the substep count n), exact at both ends.
fx::Len lerp_tick(fx::Len start, fx::Len end, uint32_t j, const InvariantDivisor& by_n) {
  if (j == 0) return start;
  if (j == by_n.d) return end;
  return fx::sat_i32(int64_t{start} + div_round_by((int64_t{end} - start) * j, by_n));
}

// (end - start) / n as a displacement per substep, Q28.36.
int64_t step_of(fx::Len start, fx::Len end, const InvariantDivisor& by_n) {
  const int64_t whole = (int64_t{end} - start) * (int64_t{1} << kFineExtraBits);  // < 2^49
  return by_n.d == 1 ? whole : div_round_by(whole, by_n);
}

LayerStatus bad_input(const char* field, const char* problem, int64_t value = 0, bool show = false) {
  return muscle::layer_fail(LayerError::kBadInput, "skin dynamic step", -1, field, problem, value, show);
}

// Gershgorin bound of the stiffness matrix's largest eigenvalue divided by
// the mass, Q16.16 1/s^2: max over vertices of (k_a + 2 sum k_e + sum k_r)
// times the gain k_scale / m. Uses s->weight as scratch.
int64_t largest_omega_squared(const SkinModel& model, int64_t spring_gain, SkinState* s) {
  const uint32_t n = model.vertex_count;
  for (uint32_t v = 0; v < n; ++v) s->weight[v] = model.anchor_stiffness[v];
  for (const Edge& e : model.edges) {
    s->weight[e.a] += 2 * int64_t{e.k};  // <= (1 + 2 edges + bands) * 2^24 per vertex: no overflow
    s->weight[e.b] += 2 * int64_t{e.k};
  }
  for (const RubberBand& b : model.bands) s->weight[b.vertex] += b.k;
  int64_t largest = 0;
  for (uint32_t v = 0; v < n; ++v)
    if (s->weight[v] > largest) largest = s->weight[v];
  return mul_shift_sat(largest, spring_gain, kQ16FracBits);
}

void band_targets(const SkinModel& model, const muscle::MuscleState& m, std::span<fx::Len> (&out)[3]) {
  for (size_t i = 0; i < model.bands.size(); ++i) {
    const RubberBand& b = model.bands[i];
    const uint32_t at = muscle::muscle_vertex_index(m.ring_vertices, b.muscle, b.slice, b.ring_vertex);
    for (int c = 0; c < 3; ++c) out[c][i] = m.vertex[c][at];
  }
}

// Edge dashpots (LEMAN §3), explicit from the substep's start: on a,
// (h c / m) ((d_b - d_a) . e) e, the opposite on b (e: unit a -> b).
void add_edge_dashpots(const SkinModel& model, int64_t edge_gamma, SkinState* s) {
  for (const Edge& e : model.edges) {
    const fx::Vec3 w{fx::sub_sat(s->position[0][e.b], s->position[0][e.a]),
                     fx::sub_sat(s->position[1][e.b], s->position[1][e.a]),
                     fx::sub_sat(s->position[2][e.b], s->position[2][e.a])};
    fx::Vec3 dir{};
    if (!fx::normalize_to_unit(w, &dir)) continue;
    const int64_t u[3] = {dir.x, dir.y, dir.z};
    int64_t relative = 0;  // (d_b - d_a) . e, Q28.36: |d| <= 2^50
    for (int c = 0; c < 3; ++c)
      relative += fx::mul_shift_round(s->velocity[c][e.b] - s->velocity[c][e.a], u[c], fx::kUnitFracBits);
    const int64_t along = clamp_displacement(mul_shift_sat(edge_gamma, relative, kGainFracBits));
    for (int c = 0; c < 3; ++c) {
      const int64_t a = fx::mul_shift_round(along, u[c], fx::kUnitFracBits);
      s->force[c][e.a] = fx::add_sat_i64(s->force[c][e.a], a);
      s->force[c][e.b] = fx::add_sat_i64(s->force[c][e.b], -a);
    }
  }
}

// Largest 2 c_e degree / m over vertices, Q16.16 1/s (the edge dashpots'
// Gershgorin bound). Uses s->weight as scratch.
int64_t largest_edge_damping(const SkinModel& model, int64_t edge_c, SkinState* s) {
  for (uint32_t v = 0; v < model.vertex_count; ++v) s->weight[v] = 0;
  for (const Edge& e : model.edges) {
    ++s->weight[e.a];
    ++s->weight[e.b];
  }
  int64_t degree = 0;
  for (uint32_t v = 0; v < model.vertex_count; ++v)
    if (s->weight[v] > degree) degree = s->weight[v];
  // Saturates instead of overflowing (a huge product is refused anyway).
  return edge_c > INT64_MAX / (2 * degree + 1) ? INT64_MAX : 2 * degree * edge_c;
}

// One substep of n, the one that starts at t = j / n of the tick (j = 0..n-1):
// displacements from the springs and the external field, the implicit
// dashpots, then x += d'. The springs pull towards the anchors and band
// targets at the substep's start, where the positions are (symplectic
// Euler takes every force at t_j): a bone that jumps within a tick then
// pulls on the skin only from the next substep on.
void integrate(const SkinModel& model, const Gains& g, uint32_t j, SkinState* s) {
  const uint32_t count = model.vertex_count;
  for (int c = 0; c < 3; ++c)
    for (uint32_t v = 0; v < count; ++v) s->force[c][v] = g.external[c];
  for (uint32_t v = 0; v < count; ++v) s->weight[v] = 0;
  // Edges (§5.2, eq. 1), from the positions at the substep's start (Jacobi).
  for (const Edge& e : model.edges) {
    int64_t a[3];
    if (!edge_displacement(model.params, e, g.spring_h2, s->position, a)) continue;
    for (int c = 0; c < 3; ++c) {
      s->force[c][e.a] = fx::add_sat_i64(s->force[c][e.a], a[c]);
      s->force[c][e.b] = fx::add_sat_i64(s->force[c][e.b], -a[c]);
    }
  }
  if (g.edge_gamma != 0) add_edge_dashpots(model, g.edge_gamma, s);
  // Rubber bands (§5.5): zero-length spring plus dashpot to the moving
  // target; s->weight sums the vertex's band gammas (its extra damping).
  constexpr int kToFine = kGainFracBits + 20 - 20 - kFineExtraBits;  // Q30 x Len -> Q28.36
  for (size_t i = 0; i < model.bands.size(); ++i) {
    const RubberBand& b = model.bands[i];
    const int64_t kappa = mul_shift_sat(b.k, g.spring_h2, kStiffnessFracBits + kSpringFracBits - kGainFracBits);
    for (int c = 0; c < 3; ++c) {
      const fx::Len target = lerp_tick(s->band_start[c][i], s->band_end[c][i], j, g.by_substeps);
      const int64_t target_d = step_of(s->band_start[c][i], s->band_end[c][i], g.by_substeps);
      const int64_t a = mul_shift_sat(kappa, int64_t{target} - s->position[c][b.vertex], kToFine) +
                        mul_shift_sat(g.band_gamma, target_d, kGainFracBits);
      s->force[c][b.vertex] = fx::add_sat_i64(s->force[c][b.vertex], a);
    }
    s->weight[b.vertex] = fx::add_sat_i64(s->weight[b.vertex], g.band_gamma);
  }
  for (uint32_t v = 0; v < count; ++v) {
    const int64_t kappa =
        mul_shift_sat(model.anchor_stiffness[v], g.spring_h2, kStiffnessFracBits + kSpringFracBits - kGainFracBits);
    const int64_t factor =
        s->weight[v] == 0 ? g.anchor_only_factor : damping_factor(fx::add_sat_i64(s->weight[v], g.anchor_gamma));
    for (int c = 0; c < 3; ++c) {
      // The anchor's linear path across the tick, by its move per substep.
      const int64_t anchor_d = s->anchor_step[c][v];
      const fx::Len anchor = j == 0 ? s->anchor_start[c][v]
                                    : fx::sat_i32(fx::round_shift((int64_t{s->anchor_start[c][v]} << kFineExtraBits) +
                                                                      anchor_d * static_cast<int64_t>(j),
                                                                  kFineExtraBits));
      int64_t a = fx::add_sat_i64(s->force[c][v], mul_shift_sat(kappa, int64_t{anchor} - s->position[c][v], kToFine));
      a = fx::add_sat_i64(a, mul_shift_sat(g.anchor_gamma, anchor_d, kGainFracBits));
      // (1 + h D) d' = d + h^2 a + sum (h c_i / m) d_i.
      const int64_t next = clamp_displacement(
          mul_shift_sat(clamp_displacement(s->velocity[c][v] + clamp_displacement(a)), factor, kGainFracBits));
      s->velocity[c][v] = next;
      const int64_t fine = fx::clamp_i64(s->fine[c][v] + next, kFineMin, kFineMax);
      s->fine[c][v] = fine;
      s->position[c][v] = fx::sat_i32(fx::round_shift(fine, kFineExtraBits));
    }
  }
}

}  // namespace

uint32_t skin_substeps(const SkinSolverParams& p, uint32_t tick_hz) {
  if (tick_hz == 0) return 0;
  const uint32_t n = p.substep_hz <= tick_hz ? 1u : (p.substep_hz + tick_hz - 1) / tick_hz;
  return n > p.max_substeps ? 0 : n;
}

LayerStatus skin_dynamic_step(const SkinModel& model, const muscle::MuscleModel& muscles,
                              const muscle::MuscleState& mstate, std::span<const fx::Mat34> bones, const SkinTick& tick,
                              SkinState* state) {
  (void)muscles;
  SkinState& s = *state;
  const SkinSolverParams& sp = model.solver;
  if (tick.tick_hz == 0 || tick.tick_hz > kMaxTickHz)
    return bad_input("tick_hz", "must be 1..100000 in dynamic mode", tick.tick_hz, true);
  // LEMAN §6.11's relaxation takes one implicit step per tick.
  const bool relaxation = model.surface.integrator == static_cast<uint8_t>(SkinIntegrator::kRelaxation);
  const uint32_t n = relaxation ? 1u : skin_substeps(sp, tick.tick_hz);
  if (n == 0) return bad_input("tick_hz", "the tick needs more than max_substeps substeps", tick.tick_hz, true);
  if (s.fine[0].size() != model.vertex_count || s.band_end[0].size() != model.bands.size())
    return bad_input("state", "not initialised for a dynamic skin model");
  // Q16.16 gains per unit mass: k / m in 1/s^2, c / m in 1/s.
  const int64_t spring = fx::div_round(int64_t{sp.stiffness_scale} << kMassFracBits, sp.vertex_mass);
  const int64_t anchor_c = fx::div_round(int64_t{sp.anchor_damping} << kMassFracBits, sp.vertex_mass);
  const int64_t band_c = fx::div_round(int64_t{sp.band_damping} << kMassFracBits, sp.vertex_mass);
  const int64_t edge_c = fx::div_round(int64_t{sp.edge_damping} << kMassFracBits, sp.vertex_mass);
  const int64_t substep_rate = int64_t{tick.tick_hz} * n;  // H = 1 / h, <= 6.4e6
  // Stability (symplectic Euler): h * omega_max <= 1, i.e. omega^2 <= H^2.
  const int64_t h2 = (substep_rate * substep_rate) << kQ16FracBits;  // < 2^62
  const int64_t omega2 = largest_omega_squared(model, spring, &s);
  if (!relaxation && omega2 > h2)
    return bad_input("substep_hz", "substeps too long for the skin's stiffest vertex (h * omega > 1)",
                     fx::isqrt_fast(static_cast<uint64_t>(omega2 >> kQ16FracBits)), true);
  // Explicit edge dashpots: h * gamma_max <= 1, i.e. gamma_max <= H.
  if (!relaxation && edge_c != 0 && largest_edge_damping(model, edge_c, &s) > (substep_rate << kQ16FracBits))
    return bad_input("substep_hz", "substeps too long for the edge dashpots (h * 2 c degree / m > 1)", sp.edge_damping,
                     true);
  Gains g;
  g.by_substeps = invariant_divisor(n);
  // h^2 k / m: Q16.16 * 2^30 / H^2 -> Q46, rounded once per division by H.
  g.spring_h2 = per_substep(per_substep(spring, 15, substep_rate), 15, substep_rate);
  g.anchor_gamma = per_substep(anchor_c, kGainFracBits - kQ16FracBits, substep_rate);
  g.band_gamma = per_substep(band_c, kGainFracBits - kQ16FracBits, substep_rate);
  g.edge_gamma = per_substep(edge_c, kGainFracBits - kQ16FracBits, substep_rate);
  g.anchor_only_factor = damping_factor(g.anchor_gamma);
  // h^2 (gravity - a_base): Q24.8 * 2^28 / H^2 -> Q28.36 (|g - a| < 2^33).
  const int64_t field[3] = {int64_t{sp.gravity.x} - tick.base_acceleration.x,
                            int64_t{sp.gravity.y} - tick.base_acceleration.y,
                            int64_t{sp.gravity.z} - tick.base_acceleration.z};
  constexpr int kFieldShift = (20 + kFineExtraBits - kAccelFracBits) / 2;  // 14 per division
  for (int c = 0; c < 3; ++c) {
    const int64_t magnitude = per_substep(per_substep(field[c] < 0 ? -field[c] : field[c], kFieldShift, substep_rate),
                                          kFieldShift, substep_rate);
    g.external[c] = field[c] < 0 ? -magnitude : magnitude;
  }

  SkinStats fresh;
  fresh.steps = s.stats.steps;
  s.stats = fresh;
  if (s.started != 0) {
    for (int c = 0; c < 3; ++c) {
      for (uint32_t v = 0; v < model.vertex_count; ++v) s.anchor_start[c][v] = s.anchor[c][v];
      for (size_t i = 0; i < model.bands.size(); ++i) s.band_start[c][i] = s.band_end[c][i];
    }
  }
  for (uint32_t v = 0; v < model.vertex_count; ++v) {
    const AnchorPoint a = map_anchor(model.anchors[v], bones, mstate);
    const fx::Len p[3] = {a.position.x, a.position.y, a.position.z};
    const fx::Unit nrm[3] = {a.normal.x, a.normal.y, a.normal.z};
    for (int c = 0; c < 3; ++c) {
      s.anchor[c][v] = p[c];
      s.normal[c][v] = nrm[c];
    }
  }
  band_targets(model, mstate, s.band_end);
  if (s.started == 0) {  // at rest on the first pose
    for (int c = 0; c < 3; ++c) {
      for (uint32_t v = 0; v < model.vertex_count; ++v) {
        s.anchor_start[c][v] = s.anchor[c][v];
        s.position[c][v] = s.anchor[c][v];
        s.velocity[c][v] = 0;
      }
      for (size_t i = 0; i < model.bands.size(); ++i) s.band_start[c][i] = s.band_end[c][i];
    }
    // At rest means at the springs' equilibrium over the muscles, not on the
    // bare anchors (the skin would spring from them into its place): the
    // static relaxation of §5.2 for kStartRelaxations rounds, where the
    // paper finds the skin close to equilibrium.
    for (uint32_t i = 0; i < kStartRelaxations; ++i) {
      relax_once(model, mstate, &s);
      estimate_surface_normals(model, &s);
      apply_reaction_constraints(model, mstate, i + 1 == kStartRelaxations ? fx::kUnitOne : model.params.reaction_gain,
                                 &s);
    }
    for (int c = 0; c < 3; ++c)
      for (uint32_t v = 0; v < model.vertex_count; ++v) s.fine[c][v] = int64_t{s.position[c][v]} << kFineExtraBits;
  }
  // Velocities to displacements per substep for the tick (d = v / H:
  // |v| <= 2^46, so v << 16 fits).
  const InvariantDivisor by_rate = invariant_divisor(substep_rate);
  for (int c = 0; c < 3; ++c)
    for (uint32_t v = 0; v < model.vertex_count; ++v)
      s.velocity[c][v] = div_round_by(s.velocity[c][v] * (int64_t{1} << kFineExtraBits), by_rate);
  // The anchors' moves per substep this tick, and the acceleration cap: an
  // anchor's velocity change from the last tick, h (step - last step), may
  // reach a_max T per tick, i.e. a_max n h^2 in substep units; the excess
  // goes to the vertex's own displacement (it is carried).
  const int64_t cap =
      tick.max_anchor_acceleration <= 0
          ? 0
          : per_substep(per_substep(int64_t{tick.max_anchor_acceleration} * n, kFieldShift, substep_rate), kFieldShift,
                        substep_rate);
  const bool comparable = s.started != 0 && s.step_rate == substep_rate;
  s.stats.carried = 0;
  for (uint32_t v = 0; v < model.vertex_count; ++v) {
    int64_t step[3], change[3];
    uint64_t change2 = 0;
    for (int c = 0; c < 3; ++c) {
      step[c] = step_of(s.anchor_start[c][v], s.anchor[c][v], g.by_substeps);
      change[c] = comparable ? step[c] - s.anchor_step[c][v] : 0;  // |each| < 2^50
      // In Len, saturated at 2^31 so that the three squares sum below 2^64.
      const uint64_t m = std::min<uint64_t>(fx::magnitude(change[c]) >> kFineExtraBits, INT32_MAX);
      change2 += m * m;
      s.anchor_step[c][v] = step[c];
    }
    if (cap == 0 || change2 == 0) continue;
    const uint64_t cap_len = std::min<uint64_t>(static_cast<uint64_t>(cap) >> kFineExtraBits, INT32_MAX);
    if (change2 <= cap_len * cap_len) continue;
    // Keep cap / |change| of the change as the skin's excitation, carry the
    // rest: ratio in Q30 (< 1 here).
    const int64_t length = fx::isqrt_fast(change2);  // Len, > cap_len
    const int64_t ratio = fx::div_round(static_cast<int64_t>(cap_len) << fx::kUnitFracBits, length);
    for (int c = 0; c < 3; ++c) {
      const int64_t kept = mul_shift_sat(change[c], ratio, fx::kUnitFracBits);
      s.velocity[c][v] = clamp_displacement(s.velocity[c][v] + change[c] - kept);
    }
    ++s.stats.carried;
  }
  s.step_rate = static_cast<uint32_t>(substep_rate);
  uint32_t candidates = 0;
  if (relaxation) {
    for (int c = 0; c < 3; ++c)
      for (uint32_t v = 0; v < model.vertex_count; ++v) s.previous[c][v] = s.position[c][v];
    candidates = relaxation_step(model, mstate, g, tick.tick_hz, &s);
  }
  for (uint32_t j = 1; !relaxation && j <= n; ++j) {
    if (j == n)
      for (int c = 0; c < 3; ++c)
        for (uint32_t v = 0; v < model.vertex_count; ++v) s.previous[c][v] = s.position[c][v];
    integrate(model, g, j - 1, &s);
    estimate_surface_normals(model, &s);  // kSurface only: the fat along the moved skin's normal (§5.6)
    candidates = list_reaction_candidates(model, mstate, &s);
    for (uint32_t pass = 0; pass < sp.constraint_passes; ++pass)
      s.stats.reactions += apply_sliding_reactions(model, mstate, candidates, &s);
  }
  // And back: v = d H, Q44.20 rig units / s.
  for (int c = 0; c < 3; ++c)
    for (uint32_t v = 0; v < model.vertex_count; ++v)
      s.velocity[c][v] = clamp_motion(mul_shift_sat(s.velocity[c][v], substep_rate, kFineExtraBits));
  uint64_t worst = 0;
  for (uint32_t v = 0; v < model.vertex_count; ++v) {
    uint64_t d2 = 0;
    for (int c = 0; c < 3; ++c) {
      const uint64_t d = fx::magnitude(int64_t{s.position[c][v]} - s.previous[c][v]);
      d2 = d >= (uint64_t{1} << 31) ? UINT64_MAX : (d2 + d * d < d2 ? UINT64_MAX : d2 + d * d);
    }
    if (d2 > worst) worst = d2;
  }
  s.stats.substeps = n;
  s.stats.omega_max = fx::isqrt_fast(static_cast<uint64_t>(omega2 >> kQ16FracBits));
  s.stats.residual = fx::sat_i32(int64_t{fx::isqrt_fast(worst)});
  // Against the normals the last reaction pass used (re-estimating them from
  // the pushed skin would tilt some fat points back in by the push's turn),
  // over the last substep's candidates: no other fat point is in reach.
  s.stats.inside_after = count_inside_of(model, mstate, fx::kUnitOne >> 10, s, s.weight.data(), candidates);
  s.started = 1;
  ++s.stats.steps;
  return {};
}

}  // namespace sinew::elastic_skin
