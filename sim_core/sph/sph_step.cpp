#include "sph_step.hpp"

#include "sim_core/fixed/wide.hpp"
#include "sim_core/layer/range_totals.hpp"
#include "sim_core/rig/message.hpp"
#include "sph_grid.hpp"
#include "sph_kernels.hpp"
#include "sph_pose.hpp"
#include "sph_yield.hpp"

namespace sinew::sph {
namespace {

constexpr int32_t kMaxForce = int32_t{1} << 30;  // newtons Q16.16: 16384 N

LayerStatus bad_input(const char* what) {
  LayerStatus s;
  s.error = LayerError::kBadInput;
  rig::MessageBuilder(s.message, sizeof s.message).text("sph step: ").text(what);
  return s;
}

// Torque of the external force about the joint axis, rig unit x N in Q12:
// ((P - c) x F) . n with P the load point (Len), F in Q16.16.
int64_t load_torque_q12(const JointFrame& f, const fx::Vec3& load_point, fx::Vec3 force) {
  const fx::Vec3 p = fx::transform_point(*f.distal, load_point);
  const int64_t r[3] = {int64_t{p.x} - f.centre.x, int64_t{p.y} - f.centre.y, int64_t{p.z} - f.centre.z};
  const int64_t F[3] = {force.x, force.y, force.z};
  const int64_t n[3] = {f.axis.x, f.axis.y, f.axis.z};
  int64_t torque = 0;
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    // |r| < 2^32, |F| <= 2^30: each product < 2^62, the difference < 2^63.
    const int64_t cross_q36 = r[b] * F[c] - r[c] * F[b];
    torque += fx::mul_shift_round(cross_q36, n[a], 54);  // Q36 x Q30 -> Q12
  }
  return torque;
}

// Tresca yield, eq. (4) of sph-elastic-joints-tresca: a particle yields
// while half the difference between its density and its unloaded one
// (rho_min, the steady state of minimum principal stress: its rest density)
// reaches tau_f. While it yields its density is not increased beyond that
// (§4.2: "we do not increase the density by more than that") and it takes no
// external force; it takes force again once its density falls back below
// the limit.
void density_and_yield(SphState* st, bool tresca, const layer::Workers* workers) {
  const SphModel& m = *st->model;
  compute_density(st);
  st->yielded_particles = layer::run_ranges_summed(workers, m.particle_count(), [&](uint32_t begin, uint32_t end) {
    uint32_t yielded = 0;
    for (uint32_t i = begin; i < end; ++i) {
      Dens rho = st->density[i];
      const int64_t limit = int64_t{st->rest_density[i]} + 2 * int64_t{m.params.tau_f};
      const bool yields = tresca && rho >= limit;
      if (yields) rho = static_cast<Dens>(limit);  // limit <= the density, below 2^31
      st->yielded[i] = yields ? 1 : 0;
      yielded += yields ? 1u : 0u;
      st->density[i] = rho;
      // Equation of state p = k_p (rho - rho0), Mueller 2003; k_p is in pressure_gain.
      st->pressure[i] = fx::sat_i32(int64_t{rho} - st->rest_density[i]);
      st->inv_density[i] = static_cast<fx::Unit>(fx::div_round(int64_t{1} << 54, rho < kDensOne ? kDensOne : rho));
    }
    return yielded;
  });
}

// One side of a pair: the terms particle i takes from its neighbour j, with
// d = (x_i - x_j) / h, dv = v_j - v_i, kernel factors spiky and visc at its
// q^2 and inv_j = 1 / rho_j, added to sum[0..2] (pressure, Q24) and
// sum[3..5] (viscosity, Len per substep).
inline void add_side(int64_t psum, int64_t inv_j, int64_t spiky, int64_t visc, const int64_t d[3], const int64_t dv[3],
                     int64_t sum[6], fx::Saturation& sat) {
  // Pressure, symmetric form of Mueller 2003 eq. (10) with the spiky
  // gradient: (p_i + p_j) / (2 rho_j) (1 - q)^2 / q (r_ij / h).
  const int64_t t = fx::round_shift(psum * inv_j, 31);                  // Q24, halved
  const int64_t tg = fx::sat_i32(fx::round_shift(t * spiky, 24), sat);  // Q24
  // Viscosity, Mueller 2003 eq. (14): (v_j - v_i) / rho_j * laplacian.
  const int64_t lw = fx::round_shift(visc * inv_j, 30);  // Q30
  for (int a = 0; a < 3; ++a) {
    sum[a] += fx::round_shift(tg * d[a], 30);
    sum[3 + a] += fx::round_shift(dv[a] * lw, 30);
  }
}

// The colour field's terms particle i takes from j (Mueller 2003 §4.4, poly6
// colour c_s = sum_j w_ij / rho_j): gradient (1 - s)^2 d / rho_j into
// sum[0..2] and Laplacian (1 - s)(3 - 7 s) / rho_j into sum[3], all Q30
// (the common factor -6 is in the gain). Each term is below 3 x 2^30.
inline void add_colour_side(uint32_t s, int64_t inv_j, const int64_t d[3], int64_t sum[4]) {
  int64_t g, l;
  colour_factors(s, &g, &l);
  const int64_t gw = fx::round_shift(g * inv_j, 30);  // Q30, <= 2^30
  for (int a = 0; a < 3; ++a) sum[a] += fx::round_shift(gw * d[a], 30);
  sum[3] += fx::round_shift(l * inv_j, 30);
}

// Surface-tension velocity change of particle i (Len per substep, into
// out[3]): a = -sigma laplacian(c_s) n / |n| / rho_i, Mueller 2003 eq. (19),
// only where |n| >= kTensionNormalMin. With n = -6 G / h and laplacian =
// -6 L / h^2 (G, L the sums above) and m / rho = h^3 / (C rho_hat) this is
// -(6 sigma h / (m C)) (L / rho_hat_i) G / |G|: the gain carries
// 6 sigma h dt^2 / (m C unit).
void tension_of(const SphState& st, uint32_t i, fx::Unit gain, int64_t out[3], fx::Saturation& sat) {
  out[0] = out[1] = out[2] = 0;
  // G and L below 96 x 3 x 2^30 (kMaxNeighbours terms): Q30 -> Q24 fits int32.
  const fx::Vec3 g{fx::sat_i32(fx::round_shift(st.colour_gradient_sum[0][i], 6), sat),
                   fx::sat_i32(fx::round_shift(st.colour_gradient_sum[1][i], 6), sat),
                   fx::sat_i32(fx::round_shift(st.colour_gradient_sum[2][i], 6), sat)};
  // |G| >= kTensionNormalMin (Q30), compared squared in Q48: |G|^2 < 3 x 2^62.
  const int64_t min24 = kTensionNormalMin >> 6;
  const int64_t g2 = fx::dot_wide(g, g);
  if (g2 < min24 * min24) return;
  fx::Vec3 unit;
  if (!fx::normalize_to_unit(g, &unit)) return;
  // The particle's own term (j = i: s = 0, factor 3) completes the sum, so
  // the Laplacian vanishes in a uniform bulk. L / rho_hat_i in Q24,
  // saturated to int32 (|L| < 2^39, inv <= 2^30: the product < 2^69 is
  // formed in 128 bits).
  const int64_t inv_i = st.inv_density[i];
  const int64_t l = st.colour_laplacian_sum[i] + 3 * inv_i;  // Q30
  const int64_t l24 = fx::sat_i32(fx::mul_shift_round(l, inv_i, 36), sat);
  // Q24 x Q30 gain -> Len (Q20): below 2^31 x 2^30 / 2^34 = 2^27.
  const int64_t magnitude = fx::round_shift(l24 * gain, 34);
  const int32_t u[3] = {unit.x, unit.y, unit.z};
  for (int a = 0; a < 3; ++a) out[a] = -fx::round_shift(magnitude * u[a], 30);
}

// The pair terms of one segment of pairs, added to the per-particle sums.
// Each pair's kernel factors and velocity difference are computed once for
// both sides (the factors twice only where its sides' q^2 differ). The
// per-particle sums are int64 and never saturate (each term below 2^32, at
// most 96 per particle), so their order is free: the same words as one list
// per particle, and as each particle gathering its own (gather()). Pairs come
// grouped by a (the search's order), so a's sums stay in registers until a
// changes. kTension adds the colour field's sums in the same pass.
template <bool kTension>
struct PairTerms {
  static constexpr size_t kSums = kTension ? 10 : 6;
  const Dens* pressure;
  const fx::Unit* inv_density;
  const fx::Len* velocity[3];
  int64_t* sums[10];

  explicit PairTerms(SphState* st)
      : pressure(st->pressure.data()),
        inv_density(st->inv_density.data()),
        velocity{st->velocity[0].data(), st->velocity[1].data(), st->velocity[2].data()},
        sums{st->pressure_sum[0].data(),        st->pressure_sum[1].data(),        st->pressure_sum[2].data(),
             st->viscosity_sum[0].data(),       st->viscosity_sum[1].data(),       st->viscosity_sum[2].data(),
             st->colour_gradient_sum[0].data(), st->colour_gradient_sum[1].data(), st->colour_gradient_sum[2].data(),
             st->colour_laplacian_sum.data()} {}

  // Returns the pair terms saturated (a local count: stores to the sums
  // cannot then alias it, so it stays in a register).
  uint32_t add(const SphPair* pairs, uint32_t count) const {
    fx::Saturation pair_sat;
    uint32_t current = count != 0 ? pairs[0].a : 0;
    int64_t acc[kSums] = {};
    for (uint32_t k = 0; k < count; ++k) {
      const SphPair& e = pairs[k];
      const uint32_t a = e.a, b = e.b;
      if (a != current) {
        for (size_t c = 0; c < kSums; ++c) {
          sums[c][current] += acc[c];
          acc[c] = 0;
        }
        current = a;
      }
      const int64_t psum = int64_t{pressure[a]} + pressure[b];
      int32_t spiky_ab, visc_ab;
      kernel_factors(e.s_ab, &spiky_ab, &visc_ab);
      const int64_t d[3] = {e.d[0], e.d[1], e.d[2]};
      const int64_t dv[3] = {int64_t{velocity[0][b]} - velocity[0][a], int64_t{velocity[1][b]} - velocity[1][a],
                             int64_t{velocity[2][b]} - velocity[2][a]};
      if ((e.sides & 1u) != 0) {
        add_side(psum, inv_density[b], spiky_ab, visc_ab, d, dv, acc, pair_sat);
        if constexpr (kTension) add_colour_side(e.s_ab, inv_density[b], d, acc + 6);
      }
      if ((e.sides & 2u) != 0) {
        // b's side: each axis negated, one LSB up where it rounded on a half.
        const int64_t d_ba[3] = {-d[0] + (e.half & 1u), -d[1] + ((e.half >> 1) & 1u), -d[2] + ((e.half >> 2) & 1u)};
        const int64_t dv_ba[3] = {-dv[0], -dv[1], -dv[2]};
        int32_t spiky_ba = spiky_ab, visc_ba = visc_ab;
        if (e.s_ba != e.s_ab) kernel_factors(e.s_ba, &spiky_ba, &visc_ba);
        int64_t b_sum[kSums] = {};
        add_side(psum, inv_density[a], spiky_ba, visc_ba, d_ba, dv_ba, b_sum, pair_sat);
        if constexpr (kTension) add_colour_side(e.s_ba, inv_density[a], d_ba, b_sum + 6);
        for (size_t c = 0; c < kSums; ++c) sums[c][b] += b_sum[c];
      }
    }
    if (count != 0)
      for (size_t c = 0; c < kSums; ++c) sums[c][current] += acc[c];
    return pair_sat.events;
  }

  // The gathered pairs (SphState::gathered): each particle of [begin, end)
  // sums its own side of its runs as a and as b, the same terms as add()'s,
  // and stores its sums. Returns the pair terms saturated.
  uint32_t gather(const SphState& st, uint32_t begin, uint32_t end) const {
    fx::Saturation pair_sat;
    const SphPair* const pairs = st.pairs.data();
    for (uint32_t i = begin; i < end; ++i) {
      int64_t acc[kSums] = {};
      for (uint32_t k = st.run_first[i]; k < st.run_first[i] + st.run_count[i]; ++k) {
        const SphPair& e = pairs[k];
        if ((e.sides & 1u) == 0) continue;
        const uint32_t b = e.b;
        int32_t spiky, visc;
        kernel_factors(e.s_ab, &spiky, &visc);
        const int64_t d[3] = {e.d[0], e.d[1], e.d[2]};
        const int64_t dv[3] = {int64_t{velocity[0][b]} - velocity[0][i], int64_t{velocity[1][b]} - velocity[1][i],
                               int64_t{velocity[2][b]} - velocity[2][i]};
        add_side(int64_t{pressure[i]} + pressure[b], inv_density[b], spiky, visc, d, dv, acc, pair_sat);
        if constexpr (kTension) add_colour_side(e.s_ab, inv_density[b], d, acc + 6);
      }
      for (uint32_t m = st.b_offset[i]; m < st.b_offset[i + 1]; ++m) {
        const SphPair& e = pairs[st.b_pair[m]];
        if ((e.sides & 2u) == 0) continue;
        const uint32_t a = e.a;
        int32_t spiky, visc;
        kernel_factors(e.s_ba, &spiky, &visc);
        // b's side: each axis negated, one LSB up where it rounded on a half.
        const int64_t d_ba[3] = {-int64_t{e.d[0]} + (e.half & 1u), -int64_t{e.d[1]} + ((e.half >> 1) & 1u),
                                 -int64_t{e.d[2]} + ((e.half >> 2) & 1u)};
        const int64_t dv_ba[3] = {int64_t{velocity[0][a]} - velocity[0][i], int64_t{velocity[1][a]} - velocity[1][i],
                                  int64_t{velocity[2][a]} - velocity[2][i]};
        add_side(int64_t{pressure[a]} + pressure[i], inv_density[a], spiky, visc, d_ba, dv_ba, acc, pair_sat);
        if constexpr (kTension) add_colour_side(e.s_ba, inv_density[a], d_ba, acc + 6);
      }
      for (size_t c = 0; c < kSums; ++c) sums[c][i] = acc[c];
    }
    return pair_sat.events;
  }
};

// Per-substep velocity change (Len per substep) of every particle, into
// scratch: the pair sums (PairTerms), then each particle's own terms. Pairs
// from the search over the workers are gathered by each particle in the
// same ranges (SphState::gathered); the others are scattered on the calling
// thread first.
template <bool kTension>
void accelerations(SphState* st, const JointFrame& f, const fx::Mat34& loaded, fx::Unit beta,
                   const layer::Workers* workers, fx::Saturation& sat) {
  const SphModel& m = *st->model;
  const SphParams& pr = m.params;
  const uint32_t n = m.particle_count();
  const PairTerms<kTension> terms(st);
  int64_t* const* sums = terms.sums;
  if (!st->gathered) {
    for (size_t c = 0; c < PairTerms<kTension>::kSums; ++c)
      for (uint32_t i = 0; i < n; ++i) sums[c][i] = 0;
    sat.events += terms.add(st->pairs.data(), st->pair_count);
  }
  sat.events += layer::run_ranges_summed(workers, n, [&](uint32_t begin, uint32_t end) {
    fx::Saturation part;
    if (st->gathered) part.events += terms.gather(*st, begin, end);
    for (uint32_t i = begin; i < end; ++i) {
      const fx::Vec3 xi{st->position[0][i], st->position[1][i], st->position[2][i]};
      // Load carried by the distal bone, applied as its rigid-body angular
      // acceleration beta (axis x r) at each particle bound to it, unless it
      // yields, with r the particle's rest offset on the bone as the bone
      // stands (flexed by the bend so far). Taken at the particle's own
      // position the field would follow it (a circulatory force, whose damped
      // oscillator flutters once beta > c sqrt(k_e)); taken unflexed it would
      // shear the tissue instead of turning it (docs/sph.md).
      fx::Vec3 ext{0, 0, 0};
      if (beta != 0 && m.bone[i] == static_cast<uint8_t>(Bone::kDistal) && st->yielded[i] == 0) {
        const fx::Vec3 on_bone =
            fx::transform_point(loaded, {m.rest_local[0][i], m.rest_local[1][i], m.rest_local[2][i]});
        ext = fx::scale(fx::cross(f.axis, fx::sub(on_bone, f.centre), 30), beta);
      }
      int64_t tension[3] = {0, 0, 0};
      if constexpr (kTension) tension_of(*st, i, pr.tension_gain, tension, part);
      const int32_t x[3] = {xi.x, xi.y, xi.z};
      const int32_t e[3] = {ext.x, ext.y, ext.z};
      for (int a = 0; a < 3; ++a) {
        // Pressure: Q24 (units of h) -> Len via gain (Q30) and h.
        const int64_t p16 = fx::sat_i32(fx::round_shift(sums[a][i], 8), part);  // Q16
        const int64_t pg = fx::round_shift(p16 * pr.pressure_gain, 30);         // Q16
        const int64_t p_len = fx::round_shift(pg * pr.h, 16);
        const int64_t v_len =
            fx::round_shift(fx::clamp_i64(sums[3 + a][i], INT32_MIN, INT32_MAX) * pr.viscosity_gain, 30);
        // Elastic pull toward the skinned rest position (§4.1 tension).
        const int64_t pull = fx::round_shift((int64_t{st->ideal[a][i]} - x[a]) * pr.elastic_gain, 30);
        st->scratch[a][i] = fx::sat_i32(p_len + v_len + pull + e[a] + tension[a], part);
      }
    }
    return part.events;
  });
}

void integrate(SphState* st, const layer::Workers* workers, fx::Saturation& sat) {
  sat.events += layer::run_ranges_summed(workers, st->model->particle_count(), [&](uint32_t begin, uint32_t end) {
    const SphModel& m = *st->model;
    fx::Saturation part;
    for (int a = 0; a < 3; ++a)
      for (uint32_t i = begin; i < end; ++i) {
        // Symplectic Euler in Len per substep: v' = damping v + a dt^2, x' = x + v'.
        // damping v is truncated toward zero (|v| < 2^31, damping <= 2^30: the
        // product is below 2^61), so every velocity decays to rest: rounded to
        // nearest, one below 1 / (2 (1 - damping)) LSB (25 at 1 kHz, 2
        // substeps, c = 40 /s) would keep itself forever and a free particle
        // would never stop.
        const int64_t kept = int64_t{st->velocity[a][i]} * m.params.damping;
        const int64_t v = (kept >= 0 ? kept >> 30 : -((-kept) >> 30)) + st->scratch[a][i];
        st->velocity[a][i] = fx::sat_i32(v, part);
        st->position[a][i] = fx::sat_i32(int64_t{st->position[a][i]} + st->velocity[a][i], part);
      }
    return part.events;
  });
}

// Best-fit rotation about the axis of the distal particles from their ideal
// to their current positions: atan2(sum n.(g x x), sum g_perp . x_perp).
fx::Angle measure_bend(const SphState& st, const JointFrame& f) {
  const SphModel& m = *st.model;
  int64_t s = 0, c = 0;
  for (uint32_t i = 0; i < m.particle_count(); ++i) {
    if (m.bone[i] != static_cast<uint8_t>(Bone::kDistal)) continue;
    const fx::Vec3 g = fx::sub({st.ideal[0][i], st.ideal[1][i], st.ideal[2][i]}, f.centre);
    const fx::Vec3 x = fx::sub({st.position[0][i], st.position[1][i], st.position[2][i]}, f.centre);
    const fx::Vec3 gx = fx::cross(g, x, 20);             // Len
    s += fx::round_shift(fx::dot_wide(gx, f.axis), 30);  // Len
    // g_perp . x_perp = g . x - (g . n)(x . n) (the flexion the distal
    // particles carry, sph-elastic-joints-tresca §4). |g . n| and |x . n|
    // reach sqrt(3) x 2^31 (offsets saturated to Len along a diagonal axis),
    // so their product (up to 3 x 2^62) is formed in 128 bits and rounded
    // once: the same value as before wherever it fitted in int64. g . x
    // saturates (dot_wide) only when both offsets lie near a corner of the
    // Len range.
    const int64_t gn = fx::round_shift(fx::dot_wide(g, f.axis), 30);
    const int64_t xn = fx::round_shift(fx::dot_wide(x, f.axis), 30);
    c += fx::round_shift(fx::dot_wide(g, x), 20) - fx::mul_shift_round(gn, xn, 20);
  }
  while (s >= (int64_t{1} << 30) || s <= -(int64_t{1} << 30) || c >= (int64_t{1} << 30) || c <= -(int64_t{1} << 30)) {
    s >>= 1;
    c >>= 1;
  }
  return fx::atan2_angle(static_cast<int32_t>(s), static_cast<int32_t>(c));
}

// Displacement of eq. (2): A(r) = sum_j m_j A_j W(r - r_j, h) / rho_j, A_j the
// particle's offset from its anchor in the flexed pose; kernel weights taken
// at rest. In normalised units m_j W / rho_j = w / rho_hat, so a vertex deep
// in the tissue takes the full displacement and one outside every kernel
// none: the interpolation itself blends SPH with the skinning result.
void skin_displacement(SphState* st, const layer::Workers* workers, fx::Saturation& sat) {
  const SphModel& m = *st->model;
  layer::run_ranges_summed(workers, m.particle_count(), [&](uint32_t begin, uint32_t end) {
    for (uint32_t i = begin; i < end; ++i) {
      const fx::Vec3 r{m.rest_local[0][i], m.rest_local[1][i], m.rest_local[2][i]};
      const bool distal = m.bone[i] == static_cast<uint8_t>(Bone::kDistal);
      const fx::Vec3 anchor = distal ? fx::transform_point(st->distal_flexed, r)
                                     : fx::Vec3{st->ideal[0][i], st->ideal[1][i], st->ideal[2][i]};
      st->scratch[0][i] = fx::sub_sat(st->position[0][i], anchor.x);
      st->scratch[1][i] = fx::sub_sat(st->position[1][i], anchor.y);
      st->scratch[2][i] = fx::sub_sat(st->position[2][i], anchor.z);
    }
    return 0u;
  });
  sat.events += layer::run_ranges_summed(workers, m.skin_count(), [&](uint32_t begin, uint32_t end) {
    fx::Saturation part;
    for (uint32_t v = begin; v < end; ++v) {
      int64_t sum[3] = {0, 0, 0};
      const size_t base = size_t{v} * kMaxVertexNeighbours;
      for (uint32_t k = 0; k < st->skin_count[v]; ++k) {
        const uint32_t j = st->skin_particle[base + k];
        const int64_t w = fx::round_shift(int64_t{st->skin_weight[base + k]} * st->inv_density[j], 30);  // Q30
        for (int a = 0; a < 3; ++a) sum[a] += fx::round_shift(int64_t{st->scratch[a][j]} * w, 30);
      }
      for (int a = 0; a < 3; ++a) st->skin_offset[a][v] = fx::sat_i32(sum[a], part);
    }
    return part.events;
  });
}

}  // namespace

LayerStatus sph_step(SphState* st, const SphInputs& in) {
  if (st == nullptr || st->model == nullptr) return bad_input("state is not initialised");
  const SphModel& m = *st->model;
  JointFrame f;
  if (!joint_frame(m, in.transforms, &f)) return bad_input("transforms: fewer than the model's joints");
  if (in.force.x < -kMaxForce || in.force.x > kMaxForce || in.force.y < -kMaxForce || in.force.y > kMaxForce ||
      in.force.z < -kMaxForce || in.force.z > kMaxForce)
    return bad_input("force: a component beyond 16384 N");
  fx::Saturation sat;
  st->stats.neighbour_overflow = 0;
  st->stats.max_neighbour_count = 0;
  st->stats.neighbour_pairs = 0;
  st->stats.candidate_builds = 0;

  // Every distal particle that does not yield takes its share of the load
  // (§4.2); a yielded one takes none until its density falls back. "When
  // the density of a particle increases beyond the yield condition, the
  // object is no longer subjected to force" (abstract): while the joint
  // yields its load is held at the torque it had when the yield began
  // (sph_yield.hpp). A measured joint's tissue takes the load too.
  const int64_t requested = fx::clamp_i64(load_torque_q12(f, m.joint.load_point, in.force), INT32_MIN, INT32_MAX);
  const JointYield before{st->joint_yielded, st->yield_torque_q12};
  const int64_t torque = held_load_torque(before, requested);
  // Angular acceleration x dt^2 of the distal bone: torque x load_gain / I.
  const fx::Unit beta = fx::sat_i32(
      fx::clamp_i64(fx::div_round(torque * m.params.load_gain, st->inertia_q12), -fx::kUnitOne, fx::kUnitOne), sat);

  compute_ideal(st, f);
  // The distal bone as it stands: the tick's pose flexed by the bend so far.
  const fx::Mat34 loaded =
      fx::mul(*f.distal, fx::mat34_from_quat(fx::quat_from_axis_angle(m.joint.axis, st->bend), {0, 0, 0}));
  // Surface tension runs only with its gain and its sums carved (sph_state.cpp).
  const bool tension = m.params.tension_gain != 0 && !st->colour_laplacian_sum.empty();
  for (uint32_t s = 0; s < m.params.substeps; ++s) {
    build_neighbours(st, f.centre, in.workers);
    density_and_yield(st, in.tresca, in.workers);
    if (tension)
      accelerations<true>(st, f, loaded, beta, in.workers, sat);
    else
      accelerations<false>(st, f, loaded, beta, in.workers, sat);
    integrate(st, in.workers, sat);
  }
  const JointYield after =
      next_joint_yield(before, in.tresca, st->yielded_particles, m.params.yield_count, requested, torque);
  st->joint_yielded = after.yielded;
  st->yield_torque_q12 = after.held_torque_q12;
  // A measured joint is not bent a second time: the particles' rotation
  // about it stays in the skin offsets below (anchored on the measured bone).
  st->bend = in.joint_measured ? fx::Angle{0} : measure_bend(*st, f);
  const fx::Mat34 flex = fx::mat34_from_quat(fx::quat_from_axis_angle(m.joint.axis, st->bend), {0, 0, 0});
  st->distal_flexed = fx::mul(*f.distal, flex);
  skin_displacement(st, in.workers, sat);
  st->stats.saturated = sat.events;
  ++st->stats.steps;
  return {};
}

bool sph_flexion_force(const SphModel& model, std::span<const fx::Mat34> transforms, int32_t newtons, fx::Vec3* out) {
  *out = {0, 0, 0};
  JointFrame f;
  if (!joint_frame(model, transforms, &f)) return false;
  const fx::Vec3 lever = fx::sub(fx::transform_point(*f.distal, model.joint.load_point), f.centre);
  fx::Vec3 direction;  // Q2.30
  if (!fx::normalize_to_unit(fx::cross(f.axis, lever, 30), &direction)) return true;
  const int32_t n = newtons < -kMaxForce ? -kMaxForce : (newtons > kMaxForce ? kMaxForce : newtons);
  // A unit direction may exceed 2^30 by its rounding: clamp each component
  // too, so a force at the limit is one sph_step accepts.
  const auto component = [n](fx::Unit d) {
    return static_cast<int32_t>(fx::clamp_i64(fx::mul_by_unit(n, d), -kMaxForce, kMaxForce));
  };
  *out = {component(direction.x), component(direction.y), component(direction.z)};
  return true;
}

void sph_apply_skin(const SphState& st, std::span<fx::Len> position[3]) {
  const SphModel& m = *st.model;
  for (uint32_t v = 0; v < m.skin_count(); ++v) {
    const uint32_t idx = m.skin_vertex[v];
    for (int a = 0; a < 3; ++a)
      if (idx < position[a].size()) position[a][idx] = fx::add_sat(position[a][idx], st.skin_offset[a][v]);
  }
}

}  // namespace sinew::sph
