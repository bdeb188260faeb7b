// Follow-through of a stopping arm (LEMAN §3): the built-in arm's dynamic
// skin, its elbow flexed and then held, against an independent
// double-precision integration of the same mass-spring system, written
// from the equations (RK4): the overshoot past the final rest position and
// the settling time of the vertices that swing furthest.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <vector>

#include "tests/sim_core/muscle/anatomy_fixture.hpp"

using sinew::test::ArmAnatomy;
namespace ab = sinew::anatomy_build;
namespace es = sinew::elastic_skin;

namespace {

// The motion, at the fixture's 1 kHz tick: the elbow flexes from 0 to 60
// degrees at a constant rate over 0.2 s, then holds for 0.8 s, longer than
// the settling envelope below (checked).
constexpr uint32_t kArmTickHz = 1000;
constexpr int kArmStopTick = 200;
constexpr int kArmEndTick = 1000;
constexpr double kArmFlexDegrees = 60.0;
// The oracle's RK4 steps per tick: one, h = 1 ms. Fourth order against
// the runtime's first. RK4 is stable to h omega = 2.8; the stiffest mode
// (h omega_max = 0.82 with the tissue defaults) is a membrane mode the
// watched swing hardly holds, while the swing's own modes, near the
// anchors' 10 Hz, have h omega ~ 0.06, where RK4's error per step,
// (h omega)^5 / 120, is below 1e-8 of their amplitude; 4 steps a tick
// move the oracle's overshoots by less than 1 um (measured), while each
// step more a tick adds seconds under the sanitizers.
constexpr int kArmRk4PerTick = 1;
constexpr size_t kArmWatched = 8;  // the vertices with the largest follow-through
constexpr double kArmBand = 0.01;  // settling band: 1 % of the vertex's motion
constexpr double kArmRoundingLsb = 16;

double arm_elbow_degrees(int tick) { return kArmFlexDegrees * std::min(tick, kArmStopTick) / kArmStopTick; }

double arm_norm(const double* a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

// The oracle: the mass-spring system of skin_model.hpp written from the
// equations, in SI units, positions and velocities 3 doubles per vertex:
//   m dv/dt = sum_edges k_e' (|w| - rest) w / |w|          (eq. 1; k_e' by the §5.2 push-back rule)
//           + k_a (A - x) + c_a (dA/dt - v)                 (eq. 2, with the anchor dashpot)
//           + sum_bands k_r (T - x) + c_r (dT/dt - v)       (§5.5 rubber bands)
//           + m g
// The anchors A and band targets T are the prescribed motion: the
// runtime's values at the ends of each tick, linear in between.
struct ArmOracle {
  uint32_t n = 0;
  double mass = 0, anchor_c = 0, band_c = 0, push_back = 0, compression_band = 0;
  double gravity[3] = {};
  std::vector<double> anchor_k, edge_k, edge_rest, band_k;
  std::vector<uint32_t> edge_a, edge_b, band_vertex;
  std::vector<double> x, v;            // 3 n
  std::vector<double> a0, a1, t0, t1;  // anchors (3 n) and band targets (3 per band) at the tick's start and end
  std::vector<double> av, tv;          // their velocities across the tick
  std::vector<double> f, xs, vs, sum_x, sum_v;

  void resize() {
    for (auto* p : {&x, &v, &a0, &a1, &av, &f, &xs, &vs, &sum_x, &sum_v}) p->assign(3 * size_t{n}, 0);
    t0.assign(3 * band_vertex.size(), 0);
    t1 = tv = t0;
  }
  // The largest Gershgorin row sum of the stiffness matrix, k_a + 2 sum k_e
  // + sum k_r (N/m): the runtime's stability check takes the same bound.
  double gershgorin() const {
    std::vector<double> row(anchor_k);
    for (size_t e = 0; e < edge_a.size(); ++e) row[edge_a[e]] += 2 * edge_k[e], row[edge_b[e]] += 2 * edge_k[e];
    for (size_t b = 0; b < band_vertex.size(); ++b) row[band_vertex[b]] += band_k[b];
    return *std::max_element(row.begin(), row.end());
  }
  // §5.2: a compressed edge's stiffness multiplier, 1 at excess 0 down to
  // push_back at excess -compression_band * rest, linear in between.
  double push_back_factor(double excess, double rest) const {
    if (excess >= 0) return 1.0;
    const double band = compression_band * rest;
    return band > 0 && -excess < band ? 1.0 - (1.0 - push_back) * -excess / band : push_back;
  }
  // The forces (N) at positions p and velocities q (null: springs and
  // gravity only), the anchors and targets at fraction s of the tick.
  void forces(const std::vector<double>& p, const std::vector<double>* q, double s, std::vector<double>* out) const {
    std::vector<double>& force = *out;
    for (uint32_t i = 0; i < n; ++i)
      for (size_t c = 0; c < 3; ++c) {
        const size_t j = 3 * size_t{i} + c;
        force[j] = anchor_k[i] * (a0[j] + (a1[j] - a0[j]) * s - p[j]) + mass * gravity[c];
        if (q) force[j] += anchor_c * (av[j] - (*q)[j]);
      }
    for (size_t b = 0; b < band_vertex.size(); ++b)
      for (size_t c = 0; c < 3; ++c) {
        const size_t j = 3 * size_t{band_vertex[b]} + c, r = 3 * b + c;
        force[j] += band_k[b] * (t0[r] + (t1[r] - t0[r]) * s - p[j]);
        if (q) force[j] += band_c * (tv[r] - (*q)[j]);
      }
    for (size_t e = 0; e < edge_a.size(); ++e) {
      const size_t a = 3 * size_t{edge_a[e]}, b = 3 * size_t{edge_b[e]};
      const double w[3] = {p[b] - p[a], p[b + 1] - p[a + 1], p[b + 2] - p[a + 2]};
      const double len = arm_norm(w), excess = len - edge_rest[e];
      const double g = edge_k[e] * push_back_factor(excess, edge_rest[e]) * excess / len;
      for (size_t c = 0; c < 3; ++c) {
        force[a + c] += g * w[c];
        force[b + c] -= g * w[c];
      }
    }
  }
  // Classical RK4 across one tick of dt seconds, in `steps` equal steps.
  void tick(double dt, int steps) {
    for (size_t j = 0; j < av.size(); ++j) av[j] = (a1[j] - a0[j]) / dt;
    for (size_t j = 0; j < tv.size(); ++j) tv[j] = (t1[j] - t0[j]) / dt;
    const double h = dt / steps, inverse_mass = 1 / mass;
    for (int k = 0; k < steps; ++k) {
      const double at[4] = {double(k) / steps, (k + 0.5) / steps, (k + 0.5) / steps, double(k + 1) / steps};
      const double next[3] = {h / 2, h / 2, h}, weight[4] = {1, 2, 2, 1};
      for (int stage = 0; stage < 4; ++stage) {
        forces(stage == 0 ? x : xs, stage == 0 ? &v : &vs, at[stage], &f);
        for (size_t j = 0; j < x.size(); ++j) {
          const double dx = stage == 0 ? v[j] : vs[j], dv = f[j] * inverse_mass;
          sum_x[j] = stage == 0 ? dx : sum_x[j] + weight[stage] * dx;
          sum_v[j] = stage == 0 ? dv : sum_v[j] + weight[stage] * dv;
          if (stage < 3) xs[j] = x[j] + next[stage] * dx, vs[j] = v[j] + next[stage] * dv;
        }
      }
      for (size_t j = 0; j < x.size(); ++j) x[j] += h / 6 * sum_x[j], v[j] += h / 6 * sum_v[j];
    }
  }
  // The static equilibrium at the tick's end (forces zero), from the
  // current positions, by Polyak's heavy ball for a stiffness between mu
  // and L: L the Gershgorin bound, mu a quarter of the weakest anchor's
  // (compressed edges at the flexed elbow, whose push-back weakens as they
  // shorten, soften the stiffness below the anchors' there; the potential
  // is not convex everywhere, which rules out conjugate gradients from
  // afar). Stops once |F| / mu, the distance to the rest while the
  // stiffness there is at least mu, is below `tolerance` (m).
  bool equilibrium(double tolerance, std::vector<double>* rest) const {
    const double mu = *std::min_element(anchor_k.begin(), anchor_k.end()) / 4;
    const double big = std::sqrt(gershgorin()), small = std::sqrt(mu);
    const double alpha = 4 / ((big + small) * (big + small));
    const double beta = ((big - small) / (big + small)) * ((big - small) / (big + small));
    std::vector<double> p = x, previous = x, force(x.size());
    for (int iteration = 0; iteration < 20000; ++iteration) {
      forces(p, nullptr, 1.0, &force);
      if (std::sqrt(std::inner_product(force.begin(), force.end(), force.begin(), 0.0)) / mu < tolerance) {
        *rest = p;
        return true;
      }
      for (size_t j = 0; j < p.size(); ++j) {
        const double next = p[j] + alpha * force[j] + beta * (p[j] - previous[j]);
        previous[j] = p[j];
        p[j] = next;
      }
    }
    return false;
  }
};

// The last tick (counted from the stop) at which deviation[k n + i] >
// band; -1 if none.
int arm_last_above(const std::vector<float>& deviation, uint32_t n, uint32_t i, double band) {
  int last = -1;
  for (size_t k = 0; k * n < deviation.size(); ++k)
    if (deviation[k * n + i] > band) last = static_cast<int>(k);
  return last;
}

}  // namespace

TEST(SkinDynamicArmOracle, StoppingElbowFollowsThroughAndSettlesLikeAnIndependentIntegration) {
  // The arm's anatomy at its defaults with the dynamic skin (no gravity by
  // default), its two primitives inactive: the reaction constraint is a
  // position projection after each substep, not a force the ODE could
  // integrate, so the comparison is exact only without it (with the
  // primitives active, fat points are pushed out every tick even at rest).
  ab::SkinSolverSpec solver;
  ArmAnatomy arm([&](ab::AnatomySpec& s) {
    s.skin.solver.dynamic = true;
    s.skin.solver.relaxation = false;  // the explicit integrator, which this oracle integrates
    for (ab::PrimitiveSpec& p : s.primitives) p.active = false;
    solver = s.skin.solver;
  });
  ASSERT_TRUE(arm.ok()) << arm.error();
  const es::SkinModel& model = arm.skin_model();
  ASSERT_GE(arm.input("elbow.0"), 0);

  // The oracle's system, in SI (the built-in arm's model unit is the
  // metre). The solver's mass (kg), spring scale (N/m per unit model
  // stiffness) and dampings (N s/m) as the builder chose them from the
  // tissue (docs/anatomy.md, "Physical defaults"): a stiffness or a damping
  // carries its N/m or N s/m number whatever the rig unit, so a runtime
  // that read them in another unit would part from the oracle (and its
  // omega_max from the one below). From the model too: the dimensionless
  // stiffnesses (eq. 1, eq. 2, bands), the rest lengths and the push-back
  // rule; gravity from the spec.
  const auto model_stiffness = [](es::Stiffness k) { return std::ldexp(double(k), -es::kStiffnessFracBits); };
  const auto unit_fraction = [](int32_t q) { return std::ldexp(double(q), -sinew::fx::kUnitFracBits); };
  const auto q16 = [](int32_t q) { return std::ldexp(double(q), -es::kQ16FracBits); };
  ArmOracle o;
  o.n = model.vertex_count;
  o.mass = std::ldexp(double(model.solver.vertex_mass), -es::kMassFracBits);
  const double stiffness_scale = q16(model.solver.stiffness_scale);
  o.anchor_c = q16(model.solver.anchor_damping);
  o.band_c = q16(model.solver.band_damping);
  for (size_t c = 0; c < 3; ++c) o.gravity[c] = solver.gravity[c];
  o.push_back = unit_fraction(model.params.push_back);
  o.compression_band = unit_fraction(model.params.compression_band);
  for (uint32_t i = 0; i < o.n; ++i) o.anchor_k.push_back(model_stiffness(model.anchor_stiffness[i]) * stiffness_scale);
  for (const es::Edge& e : model.edges) {
    o.edge_a.push_back(e.a);
    o.edge_b.push_back(e.b);
    o.edge_k.push_back(model_stiffness(e.k) * stiffness_scale);
    o.edge_rest.push_back(arm.metres(e.rest));
  }
  std::vector<double> damping(o.n, o.anchor_c);  // c per vertex: its anchor dashpot and its bands'
  for (const es::RubberBand& b : model.bands) {
    o.band_vertex.push_back(b.vertex);
    o.band_k.push_back(model_stiffness(b.k) * stiffness_scale);
    damping[b.vertex] += o.band_c;
  }
  o.resize();

  // Lockstep: each tick the runtime steps, then the oracle integrates the
  // same tick between the anchors the runtime mapped at its two ends.
  const size_t n3 = 3 * size_t{o.n};
  std::vector<double> rest(n3), direction(n3), first_anchor(n3), speed(o.n, 0), gap(o.n, 0);
  std::vector<double> peak_skin(o.n, -HUGE_VAL), peak_oracle(o.n, -HUGE_VAL);
  std::vector<int> peak_tick(o.n, 0);
  std::vector<float> deviation_skin, deviation_oracle;  // |x - rest| per tick from the stop on, per vertex
  deviation_skin.reserve(size_t{kArmEndTick - kArmStopTick + 1} * o.n);
  deviation_oracle.reserve(deviation_skin.capacity());
  uint32_t reactions = 0, anchors_moved_after_stop = 0, runtime_omega_max = 0;
  for (int k = 0; k <= kArmEndTick; ++k) {
    arm.set("elbow.0", arm_elbow_degrees(k));
    ASSERT_TRUE(arm.step().ok()) << "tick " << k;
    const es::SkinState& s = arm.skin();
    reactions += s.stats.reactions;
    runtime_omega_max = s.stats.omega_max;
    for (uint32_t i = 0; i < o.n; ++i)
      for (size_t c = 0; c < 3; ++c) o.a1[3 * i + c] = arm.metres(s.anchor[c][i]);
    for (size_t b = 0; b < o.band_vertex.size(); ++b)
      for (size_t c = 0; c < 3; ++c) o.t1[3 * b + c] = arm.metres(s.band_end[c][b]);
    if (k == 0) {  // the runtime starts at rest on the first pose's anchors
      o.a0 = o.a1, o.t0 = o.t1, o.x = o.a1, first_anchor = o.a1;
    }
    if (k > kArmStopTick)
      for (size_t j = 0; j < n3; ++j) anchors_moved_after_stop += o.a1[j] != o.a0[j];
    o.tick(1.0 / kArmTickHz, kArmRk4PerTick);
    if (k == kArmStopTick) {
      // The final pose: its rest position (to well below one LSB), and each
      // vertex's direction of motion in the last moving tick, the
      // direction it follows through.
      ASSERT_TRUE(o.equilibrium(1e-10, &rest));
      for (uint32_t i = 0; i < o.n; ++i) {
        double d[3];
        for (size_t c = 0; c < 3; ++c) d[c] = o.a1[3 * i + c] - o.a0[3 * i + c];
        const double l = arm_norm(d);
        for (size_t c = 0; c < 3; ++c) direction[3 * i + c] = l > 0 ? d[c] / l : 0;
      }
    }
    for (uint32_t i = 0; i < o.n; ++i) {
      double between[3];
      for (size_t c = 0; c < 3; ++c) between[c] = arm.skin_pos(int(c), i) - o.x[3 * i + c];
      gap[i] = std::max(gap[i], arm_norm(between));
      speed[i] = std::max(speed[i], arm_norm(&o.v[3 * i]));
    }
    if (k >= kArmStopTick)
      for (uint32_t i = 0; i < o.n; ++i) {
        double skin[3], oracle[3], along_skin = 0, along_oracle = 0;
        for (size_t c = 0; c < 3; ++c) {
          const size_t j = 3 * i + c;
          skin[c] = arm.skin_pos(int(c), i) - rest[j];
          oracle[c] = o.x[j] - rest[j];
          along_skin += skin[c] * direction[j];
          along_oracle += oracle[c] * direction[j];
        }
        peak_skin[i] = std::max(peak_skin[i], along_skin);
        if (along_oracle > peak_oracle[i]) peak_oracle[i] = along_oracle, peak_tick[i] = k - kArmStopTick;
        deviation_skin.push_back(static_cast<float>(arm_norm(skin)));
        deviation_oracle.push_back(static_cast<float>(arm_norm(oracle)));
      }
    o.a0 = o.a1, o.t0 = o.t1;
  }
  EXPECT_EQ(reactions, 0u) << "no primitive is active, so no vertex may have been projected";
  EXPECT_EQ(anchors_moved_after_stop, 0u) << "the pose holds after the stop";

  const uint32_t substeps = es::skin_substeps(model.solver, kArmTickHz);
  const double h = 1.0 / (double(kArmTickHz) * substeps);  // the runtime's substep (s)
  const double lsb = arm.metres(1);
  const double omega_max = std::sqrt(o.gershgorin() / o.mass);
  // The runtime's own stability bound (rad/s, floor) is the same Gershgorin
  // bound of the same stiffnesses and mass: equal if it carries the
  // physical constants in consistent units.
  EXPECT_NEAR(runtime_omega_max, omega_max, 1.0) << "the runtime's omega_max against the spec's constants";
  // The settling envelope: the anchor dashpots damp every vertex alike
  // (gamma = c_a / m), and edges at rest length only add stiffness (Weyl),
  // so a mode has omega^2 >= min k_a / m, the weakest anchor's, and decays
  // at least at sigma = gamma/2 - sqrt(gamma^2/4 - omega^2) (overdamped).
  // (Compressed edges soften the modes at the flexed elbow, see
  // equilibrium(); the forearm, where the watched vertices are, moves
  // rigidly and its edges keep their length.)
  const double gamma = o.anchor_c / o.mass;
  const double omega_min2 = *std::min_element(o.anchor_k.begin(), o.anchor_k.end()) / o.mass;
  const double sigma =
      gamma * gamma / 4 > omega_min2 ? gamma / 2 - std::sqrt(gamma * gamma / 4 - omega_min2) : gamma / 2;
  std::printf(
      "arm, elbow 0 -> %.0f deg in %d ms, then held: h = %.4f s, omega_max %.0f rad/s (runtime %u), slowest decay "
      "%.2f /s, LSB %.3g m, %u reactions\n",
      kArmFlexDegrees, kArmStopTick, h, omega_max, runtime_omega_max, sigma, lsb, reactions);

  std::vector<uint32_t> order(o.n);
  std::iota(order.begin(), order.end(), 0u);
  std::partial_sort(order.begin(), order.begin() + kArmWatched, order.end(),
                    [&](uint32_t a, uint32_t b) { return peak_oracle[a] > peak_oracle[b]; });
  for (size_t r = 0; r < kArmWatched; ++r) {
    const uint32_t i = order[r];
    double moved[3];
    for (size_t c = 0; c < 3; ++c) moved[c] = rest[3 * i + c] - first_anchor[3 * i + c];
    const double motion = arm_norm(moved), want = peak_oracle[i], got = peak_skin[i];
    // Skin against oracle, the bound from the integrator:
    // - symplectic Euler is first order, and the runtime takes each
    //   substep's anchor at its end: its positions run ahead of the exact
    //   ones by up to h |v|max, one substep of the vertex's fastest motion
    //   (a displacement left at the stop does not grow: the system is
    //   damped);
    // - the implicit dashpots, 1 / (1 + h gamma) per substep for
    //   exp(-h gamma), damp at ln(1 + h gamma) / h: a relative error of
    //   h gamma / 2 (2.5 % at gamma = c_a / m = 50 /s), and the springs'
    //   frequency error (h omega_max)^2 / 24, both on the swing, at most
    //   the overshoot;
    // - fixed-point rounding: 16 LSB (each substep's anchor and output
    //   roundings through the damped response's L1 gain, as in
    //   skin_dynamic_test.cpp).
    const double h_gamma = h * damping[i] / o.mass;
    const double relative = h_gamma / 2 + (h * omega_max) * (h * omega_max) / 24;
    const double bound = h * speed[i] + relative * want + kArmRoundingLsb * lsb;
    // Settling into a band B of 1 % of the motion: by then only the slow
    // overdamped mode is left, whose amplitude the swing set. The skin's
    // swing is within `bound` of the oracle's, a relative r = bound /
    // overshoot (the slow mode's own rate differs by O(h sigma), less),
    // and it runs ahead by at most one substep. So its settling time lies
    // between the oracle's for the bands B / (1 - r) and B / (1 + r), with
    // one substep (one tick here) of slack each way.
    const double band = kArmBand * motion, r_amp = bound / want;
    const int settle = arm_last_above(deviation_skin, o.n, i, band);
    const int settle_oracle = arm_last_above(deviation_oracle, o.n, i, band);
    const int earliest = arm_last_above(deviation_oracle, o.n, i, band / (1 - r_amp)) - 1;
    const int latest = arm_last_above(deviation_oracle, o.n, i, band / (1 + r_amp)) + 1;
    // The envelope from the swing's peak, where the oracle is `apex` from
    // rest. An underdamped swing x = A e^(-sigma t) cos(omega_d t - phi)
    // peaks where cos(...) = sqrt(1 - zeta^2), below its envelope, so the
    // envelope there is apex / sqrt(1 - zeta^2) (zeta = sigma / omega of the
    // slowest mode; 1 when overdamped); plus one tick for the sampling.
    const double apex = deviation_oracle[size_t(peak_tick[i]) * o.n + i];
    const double zeta2 = std::min(1.0, gamma * gamma / (4 * omega_min2));
    const double lift = zeta2 < 1 ? 1 / std::sqrt(1 - zeta2) : 1.0;
    const double envelope = peak_tick[i] + kArmTickHz * std::log(lift * apex / band) / sigma + 1;  // ticks after stop
    std::printf(
        "vertex %u: motion %.1f mm; overshoot %.3f mm (oracle %.3f, bound +-%.3f), peak %d ms after the stop; "
        "largest gap %.3f mm; settles into %.2f mm %d ms after the stop (oracle %d, bracket [%d, %d], envelope %.0f)\n",
        i, motion * 1e3, got * 1e3, want * 1e3, bound * 1e3, peak_tick[i], gap[i] * 1e3, band * 1e3, settle,
        settle_oracle, earliest, latest, envelope);
    // The physics: the skin swings past its rest (follow-through), by more
    // than rounding and by more than the comparison's own uncertainty; a
    // quasi-static skin would not overshoot at all.
    EXPECT_GT(got, kArmRoundingLsb * lsb) << "vertex " << i;
    EXPECT_GT(want, bound) << "vertex " << i;
    // The comparison: the overshoot, the whole trajectory, the settling.
    EXPECT_NEAR(got, want, bound) << "vertex " << i;
    EXPECT_LE(gap[i], bound) << "vertex " << i;
    EXPECT_GE(settle, earliest) << "vertex " << i;
    EXPECT_LE(settle, latest) << "vertex " << i;
    // And it settles, within the envelope, which the run covers.
    EXPECT_LT(envelope, kArmEndTick - kArmStopTick) << "vertex " << i;
    EXPECT_GE(settle, 0) << "vertex " << i;
    EXPECT_LE(settle, envelope) << "vertex " << i;
  }
}
