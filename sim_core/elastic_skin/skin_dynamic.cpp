#include "skin_dynamic.hpp"

#include <bit>
#include <cstdint>

#include "invariant_division.hpp"
#include "reaction.hpp"
#include "relaxation.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/wide.hpp"
#include "surface_normals.hpp"
#include "virtual_anchors.hpp"

namespace sinew::elastic_skin {
namespace {

constexpr int64_t kMotionLimit = int64_t{1} << 46;  // |v| and |a|, Q44.20
constexpr int kFineExtraBits = 16;                  // Q28.36 fine positions over Q12.20 Len
constexpr int64_t kFineMax = int64_t{INT32_MAX} << kFineExtraBits;
constexpr int64_t kFineMin = int64_t{INT32_MIN} << kFineExtraBits;

int64_t clamp_motion(int64_t v) { return fx::clamp_i64(v, -kMotionLimit, kMotionLimit); }

// round_half_up(a * b / 2^16), saturated to +-2^62 rather than overflowing.
// Operands whose bit widths sum to 62 or less multiply in 64 bits (the same
// rounding: floor((a b + 2^15) / 2^16) either way); only wider ones, which
// the skin's gains rarely reach, take the 128-bit product.
int64_t mul_q16_sat(int64_t a, int64_t b) {
  const uint64_t ma = fx::magnitude(a), mb = fx::magnitude(b);
  if (std::bit_width(ma) + std::bit_width(mb) <= 62) return fx::round_shift(a * b, kQ16FracBits);
  const fx::U128 p = fx::mul_u64(ma, mb);
  if ((p.hi >> 14) != 0) return (a < 0) != (b < 0) ? -(int64_t{1} << 62) : int64_t{1} << 62;
  return fx::mul_shift_round(a, b, kQ16FracBits);
}

// start + (end - start) * j / n, rounded: the linear path across a tick
// (by_n: the substep count n).
fx::Len lerp_tick(fx::Len start, fx::Len end, uint32_t j, const InvariantDivisor& by_n) {
  return fx::sat_i32(int64_t{start} + div_round_by((int64_t{end} - start) * j, by_n));
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
  return mul_q16_sat(largest, spring_gain);
}

void band_targets(const SkinModel& model, const muscle::MuscleState& m, std::span<fx::Len> (&out)[3]) {
  for (size_t i = 0; i < model.bands.size(); ++i) {
    const RubberBand& b = model.bands[i];
    const uint32_t at = muscle::muscle_vertex_index(m.ring_vertices, b.muscle, b.slice, b.ring_vertex);
    for (int c = 0; c < 3; ++c) out[c][i] = m.vertex[c][at];
  }
}

// Edge dashpots (LEMAN §3), explicit from the substep's start: on a,
// c/m ((v_b - v_a) . e) e, the opposite on b (e: unit a -> b).
void add_edge_dashpots(const SkinModel& model, int64_t edge_c, SkinState* s) {
  for (const Edge& e : model.edges) {
    const fx::Vec3 w{fx::sub_sat(s->position[0][e.b], s->position[0][e.a]),
                     fx::sub_sat(s->position[1][e.b], s->position[1][e.a]),
                     fx::sub_sat(s->position[2][e.b], s->position[2][e.a])};
    fx::Vec3 dir{};
    if (!fx::normalize_to_unit(w, &dir)) continue;
    const int64_t d[3] = {dir.x, dir.y, dir.z};
    int64_t relative = 0;  // (v_b - v_a) . e, Q44.20: |v| <= 2^46
    for (int c = 0; c < 3; ++c)
      relative += fx::mul_shift_round(s->velocity[c][e.b] - s->velocity[c][e.a], d[c], fx::kUnitFracBits);
    const int64_t along = clamp_motion(mul_q16_sat(edge_c, relative));
    for (int c = 0; c < 3; ++c) {
      const int64_t a = fx::mul_shift_round(along, d[c], fx::kUnitFracBits);
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

struct Gains {
  int64_t spring = 0;        // stiffness_scale / m, Q16.16 1/s^2 per unit of model stiffness
  int64_t anchor_c = 0;      // anchor_damping / m, Q16.16 1/s
  int64_t band_c = 0;        // band_damping / m, Q16.16 1/s
  int64_t edge_c = 0;        // edge_damping / m, Q16.16 1/s
  int64_t rate = 0;          // tick_hz: (end - start) * rate is a velocity
  int64_t substep_rate = 0;  // H = tick_hz * n, 1/s
  int64_t external[3] = {};  // gravity - a_base, Q44.20
  // The tick's invariant divisors: substeps n, the substep rate H, and the
  // implicit-dashpot denominator H + c_anchor / m of every vertex without
  // rubber bands (Q16.16 1/s).
  InvariantDivisor by_substeps, by_substep_rate, by_anchor_only;
  int64_t anchor_only_den = 0;
};

// One substep j of n: accelerations, implicit dashpots, then x += v' / H.
void integrate(const SkinModel& model, const Gains& g, uint32_t j, SkinState* s) {
  const uint32_t count = model.vertex_count;
  for (int c = 0; c < 3; ++c)
    for (uint32_t v = 0; v < count; ++v) s->force[c][v] = g.external[c];
  for (uint32_t v = 0; v < count; ++v) s->weight[v] = 0;
  // Edges (§5.2, eq. 1), from the positions at the substep's start (Jacobi).
  for (const Edge& e : model.edges) {
    int64_t k = 0;
    fx::Vec3 f{};
    if (!edge_pull(model.params, e, s->position, &k, &f)) continue;
    const int64_t kk = mul_q16_sat(k, g.spring);
    const int64_t a[3] = {mul_q16_sat(kk, f.x), mul_q16_sat(kk, f.y), mul_q16_sat(kk, f.z)};
    for (int c = 0; c < 3; ++c) {
      s->force[c][e.a] = fx::add_sat_i64(s->force[c][e.a], a[c]);
      s->force[c][e.b] = fx::add_sat_i64(s->force[c][e.b], -a[c]);
    }
  }
  if (g.edge_c != 0) add_edge_dashpots(model, g.edge_c, s);
  // Rubber bands (§5.5): zero-length spring plus dashpot to the moving target.
  for (size_t i = 0; i < model.bands.size(); ++i) {
    const RubberBand& b = model.bands[i];
    const int64_t kk = mul_q16_sat(b.k, g.spring);
    for (int c = 0; c < 3; ++c) {
      const fx::Len target = lerp_tick(s->band_start[c][i], s->band_end[c][i], j, g.by_substeps);
      const int64_t target_v = clamp_motion((int64_t{s->band_end[c][i]} - s->band_start[c][i]) * g.rate);
      const int64_t a = mul_q16_sat(kk, int64_t{target} - s->position[c][b.vertex]) + mul_q16_sat(g.band_c, target_v);
      s->force[c][b.vertex] = fx::add_sat_i64(s->force[c][b.vertex], a);
    }
    s->weight[b.vertex] = fx::add_sat_i64(s->weight[b.vertex], g.band_c);
  }
  const int64_t h_q16 = g.substep_rate << kQ16FracBits;
  for (uint32_t v = 0; v < count; ++v) {
    const int64_t kk = mul_q16_sat(model.anchor_stiffness[v], g.spring);
    const int64_t damping = fx::add_sat_i64(s->weight[v], g.anchor_c);  // sum c_i / m, Q16.16 1/s
    const int64_t den = fx::add_sat_i64(h_q16, damping);                // > 0
    const bool shared_den = den == g.anchor_only_den;
    for (int c = 0; c < 3; ++c) {
      const fx::Len anchor = lerp_tick(s->anchor_start[c][v], s->anchor[c][v], j, g.by_substeps);
      const int64_t anchor_v = clamp_motion((int64_t{s->anchor[c][v]} - s->anchor_start[c][v]) * g.rate);
      int64_t a = fx::add_sat_i64(s->force[c][v], mul_q16_sat(kk, int64_t{anchor} - s->position[c][v]));
      a = fx::add_sat_i64(a, mul_q16_sat(g.anchor_c, anchor_v));
      // v' - v = (a + sum c_i v_i - D v) / (H + D), D = sum c_i / m.
      const int64_t velocity = s->velocity[c][v];
      const int64_t num = clamp_motion(fx::add_sat_i64(a, -mul_q16_sat(damping, velocity)));
      const int64_t dv =
          shared_den ? div_round_by(num << kQ16FracBits, g.by_anchor_only) : fx::div_round(num << kQ16FracBits, den);
      const int64_t next = clamp_motion(velocity + dv);
      s->velocity[c][v] = next;
      // |next| <= 2^46: next << 16 fits; the step is < 2^62.
      const int64_t fine =
          fx::clamp_i64(s->fine[c][v] + div_round_by(next << kFineExtraBits, g.by_substep_rate), kFineMin, kFineMax);
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
  const uint32_t n = skin_substeps(sp, tick.tick_hz);
  if (n == 0) return bad_input("tick_hz", "the tick needs more than max_substeps substeps", tick.tick_hz, true);
  if (s.fine[0].size() != model.vertex_count || s.band_end[0].size() != model.bands.size())
    return bad_input("state", "not initialised for a dynamic skin model");
  Gains g;
  g.spring = fx::div_round(int64_t{sp.stiffness_scale} << kMassFracBits, sp.vertex_mass);
  g.anchor_c = fx::div_round(int64_t{sp.anchor_damping} << kMassFracBits, sp.vertex_mass);
  g.band_c = fx::div_round(int64_t{sp.band_damping} << kMassFracBits, sp.vertex_mass);
  g.edge_c = fx::div_round(int64_t{sp.edge_damping} << kMassFracBits, sp.vertex_mass);
  g.rate = tick.tick_hz;
  g.substep_rate = int64_t{tick.tick_hz} * n;
  g.by_substeps = invariant_divisor(n);
  g.by_substep_rate = invariant_divisor(g.substep_rate);
  g.anchor_only_den = fx::add_sat_i64(g.substep_rate << kQ16FracBits, g.anchor_c);  // as integrate() forms it
  g.by_anchor_only = invariant_divisor(g.anchor_only_den);
  // Stability (symplectic Euler): h * omega_max <= 1, i.e. omega^2 <= H^2.
  const int64_t h2 = (g.substep_rate * g.substep_rate) << kQ16FracBits;  // H <= 6.4e6: < 2^62
  const int64_t omega2 = largest_omega_squared(model, g.spring, &s);
  if (omega2 > h2)
    return bad_input("substep_hz", "substeps too long for the skin's stiffest vertex (h * omega > 1)",
                     fx::isqrt_fast(static_cast<uint64_t>(omega2 >> kQ16FracBits)), true);
  // Explicit edge dashpots: h * gamma_max <= 1, i.e. gamma_max <= H.
  if (g.edge_c != 0 && largest_edge_damping(model, g.edge_c, &s) > (g.substep_rate << kQ16FracBits))
    return bad_input("substep_hz", "substeps too long for the edge dashpots (h * 2 c degree / m > 1)", sp.edge_damping,
                     true);
  // Q24.8 -> Q44.20: |g - a| < 2^32, shifted < 2^44.
  constexpr int kToMotion = 20 - kAccelFracBits;
  g.external[0] = (int64_t{sp.gravity.x} - tick.base_acceleration.x) * (int64_t{1} << kToMotion);
  g.external[1] = (int64_t{sp.gravity.y} - tick.base_acceleration.y) * (int64_t{1} << kToMotion);
  g.external[2] = (int64_t{sp.gravity.z} - tick.base_acceleration.z) * (int64_t{1} << kToMotion);

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
        s.fine[c][v] = int64_t{s.anchor[c][v]} << kFineExtraBits;
        s.velocity[c][v] = 0;
      }
      for (size_t i = 0; i < model.bands.size(); ++i) s.band_start[c][i] = s.band_end[c][i];
    }
  }
  for (uint32_t j = 1; j <= n; ++j) {
    if (j == n)
      for (int c = 0; c < 3; ++c)
        for (uint32_t v = 0; v < model.vertex_count; ++v) s.previous[c][v] = s.position[c][v];
    integrate(model, g, j, &s);
    estimate_surface_normals(model, &s);  // kSurface only: the fat along the moved skin's normal (§5.6)
    for (uint32_t pass = 0; pass < sp.constraint_passes; ++pass)
      s.stats.reactions += apply_sliding_reactions(model, mstate, &s);
  }
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
  s.stats.residual = fx::sat_i32(int64_t{fx::isqrt_fast(worst)});
  // Against the normals the last reaction pass used (re-estimating them from
  // the pushed skin would tilt some fat points back in by the push's turn).
  s.stats.inside_after = count_inside(model, mstate, fx::kUnitOne >> 10, s);
  s.started = 1;
  ++s.stats.steps;
  return {};
}

}  // namespace sinew::elastic_skin
