// Dynamic elastic skin (LEMAN §3, §5.4-5.6): follow-through against an
// independent double-precision integration, reaction constraints (no point
// inside, tangential sliding), rubber-band damping, the fat layer, tick-rate
// independence and zero allocation.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "dynamic_skin_fixture.hpp"
#include "sim_core/muscle/primitive.hpp"
#include "tests/support/alloc_guard.hpp"

namespace es = sinew::elastic_skin;
using sinew::test::DynamicSkin;
using sinew::test::from_len;
using sinew::test::to_accel;
using sinew::test::to_len;
using sinew::test::to_q16;
using sinew::test::to_q24;

namespace {

// The chain of the follow-through tests: four vertices along x, 0.1 units
// apart, joined by edges at rest length; vertex 0 held by a stiff anchor,
// the others by weak ones, so the far end lags and swings past the stop.
constexpr int kChain = 4;
constexpr double kSpacing = 0.1;
constexpr double kEdgeK = 1.0;  // model stiffness (x stiffness_scale)
constexpr double kAnchorK[kChain] = {4.0, 0.5, 0.5, 0.5};
constexpr double kScale = 20.0;    // N per unit for model stiffness 1
constexpr double kMass = 0.01;     // kg
constexpr double kDamping = 0.04;  // N s per unit, anchor dashpots
constexpr uint32_t kSubstepHz = 4000;
// Bone path along y, exact in Len at every millisecond: rest until 0.1 s,
// then 512 LSB per ms (0.48828125 units/s) until 0.3 s, then stopped.
constexpr int64_t kStepLsbPerMs = 512;
constexpr int kStartMs = 100, kStopMs = 300;

int64_t chain_bone_lsb(int ms) {
  const int moving = std::clamp(ms, kStartMs, kStopMs) - kStartMs;
  return kStepLsbPerMs * moving;
}
double chain_bone_y(double t) {  // the same path, continuous (units)
  const double ms = std::clamp(t * 1000.0, double{kStartMs}, double{kStopMs}) - kStartMs;
  return from_len(kStepLsbPerMs) * ms;
}
double chain_bone_vy(double t) {
  return (t * 1000.0 >= kStartMs && t * 1000.0 < kStopMs) ? from_len(kStepLsbPerMs) * 1000.0 : 0.0;
}

void build_chain(DynamicSkin* s, uint32_t substep_hz = kSubstepHz) {
  for (int i = 0; i < kChain; ++i) s->add_vertex(kSpacing * i, 0, 0, kAnchorK[i]);
  for (int i = 0; i + 1 < kChain; ++i)
    s->add_edge(static_cast<uint32_t>(i), static_cast<uint32_t>(i + 1), kEdgeK, kSpacing);
  s->model.solver.stiffness_scale = to_q16(kScale);
  s->model.solver.vertex_mass = to_q24(kMass);
  s->model.solver.anchor_damping = to_q16(kDamping);
  s->model.solver.band_damping = 0;
  s->model.solver.substep_hz = substep_hz;
}

// y of every chain vertex after each tick (index = tick), at tick_hz.
std::vector<std::array<double, kChain>> run_chain(uint32_t tick_hz, double seconds, uint32_t substep_hz = kSubstepHz) {
  DynamicSkin s;
  build_chain(&s, substep_hz);
  EXPECT_TRUE(s.finish());
  std::vector<std::array<double, kChain>> out;
  const int ticks = static_cast<int>(std::lround(seconds * tick_hz));
  const int ms_per_tick = static_cast<int>(1000 / tick_hz);
  for (int k = 0; k <= ticks; ++k) {
    s.bone.t[1] = static_cast<sinew::fx::Len>(chain_bone_lsb(k * ms_per_tick));
    EXPECT_TRUE(s.step(tick_hz).ok());
    std::array<double, kChain> y{};
    for (int i = 0; i < kChain; ++i) y[static_cast<size_t>(i)] = s.pos(1, static_cast<uint32_t>(i));
    out.push_back(y);
  }
  return out;
}

// The oracle: the same mass-spring system (3-D positions, nonlinear edge
// springs at their rest length, anchor springs and dashpots to the moving
// anchors) integrated by classical RK4 in double at 40 kHz, sampled at
// tick_hz. Written from the equations, not from the implementation.
std::vector<std::array<double, kChain>> oracle_chain(uint32_t tick_hz, double seconds, double* max_speed) {
  using V = std::array<double, 3>;
  struct S {
    V x[kChain], v[kChain];
  };
  const auto accel = [](const S& s, double t, S* d) {
    const double by = chain_bone_y(t), bvy = chain_bone_vy(t);
    for (int i = 0; i < kChain; ++i) {
      const V anchor{kSpacing * i, by, 0};
      const V anchor_v{0, bvy, 0};
      for (int c = 0; c < 3; ++c) {
        d->x[i][c] = s.v[i][c];
        d->v[i][c] = (kAnchorK[i] * kScale * (anchor[c] - s.x[i][c]) + kDamping * (anchor_v[c] - s.v[i][c])) / kMass;
      }
    }
    for (int e = 0; e + 1 < kChain; ++e) {
      V w{};
      double len2 = 0;
      for (int c = 0; c < 3; ++c) {
        w[c] = s.x[e + 1][c] - s.x[e][c];
        len2 += w[c] * w[c];
      }
      const double len = std::sqrt(len2);
      for (int c = 0; c < 3; ++c) {
        const double f = kEdgeK * kScale * (len - kSpacing) * w[c] / len / kMass;
        d->v[e][c] += f;
        d->v[e + 1][c] -= f;
      }
    }
  };
  const auto axpy = [](const S& a, const S& d, double h) {
    S r = a;
    for (int i = 0; i < kChain; ++i)
      for (int c = 0; c < 3; ++c) {
        r.x[i][c] += h * d.x[i][c];
        r.v[i][c] += h * d.v[i][c];
      }
    return r;
  };
  S s{};
  for (int i = 0; i < kChain; ++i) s.x[i] = {kSpacing * i, 0, 0};
  const int per_tick = static_cast<int>(40000 / tick_hz);
  const double h = 1.0 / 40000.0;
  std::vector<std::array<double, kChain>> out;
  *max_speed = 0;
  const int ticks = static_cast<int>(std::lround(seconds * tick_hz));
  for (int k = 0; k <= ticks; ++k) {
    if (k > 0)
      for (int j = 0; j < per_tick; ++j) {
        const double t = (k - 1) / double(tick_hz) + j * h;
        S k1, k2, k3, k4;
        accel(s, t, &k1);
        accel(axpy(s, k1, h / 2), t + h / 2, &k2);
        accel(axpy(s, k2, h / 2), t + h / 2, &k3);
        accel(axpy(s, k3, h), t + h, &k4);
        for (int i = 0; i < kChain; ++i)
          for (int c = 0; c < 3; ++c) {
            s.x[i][c] += h / 6 * (k1.x[i][c] + 2 * k2.x[i][c] + 2 * k3.x[i][c] + k4.x[i][c]);
            s.v[i][c] += h / 6 * (k1.v[i][c] + 2 * k2.v[i][c] + 2 * k3.v[i][c] + k4.v[i][c]);
          }
      }
    std::array<double, kChain> y{};
    for (int i = 0; i < kChain; ++i) {
      y[static_cast<size_t>(i)] = s.x[i][1];
      *max_speed = std::max(*max_speed, std::abs(s.v[i][1]));
    }
    out.push_back(y);
  }
  return out;
}

double chain_overshoot(const std::vector<std::array<double, kChain>>& y, uint32_t tick_hz, int vertex) {
  const double final_y = chain_bone_y(1e9);
  double worst = 0;
  for (size_t k = static_cast<size_t>(kStopMs) * tick_hz / 1000; k < y.size(); ++k)
    worst = std::max(worst, y[k][static_cast<size_t>(vertex)] - final_y);
  return worst;
}

// Last time (s) |y - final| exceeds `band` (units).
double chain_settling(const std::vector<std::array<double, kChain>>& y, uint32_t tick_hz, int vertex, double band) {
  const double final_y = chain_bone_y(1e9);
  double last = 0;
  for (size_t k = 0; k < y.size(); ++k)
    if (std::abs(y[k][static_cast<size_t>(vertex)] - final_y) > band) last = double(k) / tick_hz;
  return last;
}

}  // namespace

TEST(SkinDynamic, FollowThroughMatchesAnIndependentIntegration) {
  constexpr uint32_t kHz = 1000;
  constexpr double kSeconds = 3.0;
  double max_speed = 0;
  const auto oracle = oracle_chain(kHz, kSeconds, &max_speed);
  const auto skin = run_chain(kHz, kSeconds);
  ASSERT_EQ(oracle.size(), skin.size());
  const double amplitude = chain_bone_y(1e9);  // 0.09765625 units
  for (int v : {1, kChain - 1}) {
    const double want = chain_overshoot(oracle, kHz, v), got = chain_overshoot(skin, kHz, v);
    // The physics: the vertices swing past the stop (follow-through); a
    // quasi-static skin would not overshoot at all.
    EXPECT_GT(want, 0.02 * amplitude) << "vertex " << v;
    // Symplectic Euler is first order: its positions lag the exact ones by at
    // most h * |v|max (h = 1/4000 s); the implicit dashpots change the decay
    // per substep by (h c/m)^2 / 2 (< 1e-6), i.e. under 1% over the run; plus
    // 16 LSB of fixed-point rounding.
    const double bound = max_speed / kSubstepHz + 0.01 * want + 16.0 / 1048576.0;
    EXPECT_NEAR(got, want, bound) << "vertex " << v;
    std::printf("vertex %d: overshoot %.6f (oracle %.6f, bound %.6f)", v, got, want, bound);
    // Settling into a band of 1% of the motion: with the amplitude within
    // 10% of the oracle's, the skin's settling time lies between the
    // oracle's for bands 10% wider and 10% narrower (one tick of slack).
    const double band = 0.01 * amplitude;
    const double settle = chain_settling(skin, kHz, v, band);
    EXPECT_GE(settle, chain_settling(oracle, kHz, v, 1.1 * band) - 1.0 / kHz) << "vertex " << v;
    EXPECT_LE(settle, chain_settling(oracle, kHz, v, 0.9 * band) + 1.0 / kHz) << "vertex " << v;
    // And it does settle, by the damping envelope: the dashpot acts on the
    // velocity relative to the anchor, so a bone at constant speed V leaves
    // no lag; each of its two speed steps (start, stop) swings the vertex
    // by at most V / omega_d in the anchor's frame (edges along x at their
    // rest length do not couple y motions to first order), omega_d^2 =
    // k_a s / m - (c / 2m)^2, and the swing decays as exp(-(c / 2m) t).
    // So |y - final| < band from t_stop + ln(2 V / (omega_d band)) / (c / 2m),
    // sampled at the ticks (one tick later at most).
    const double speed = chain_bone_vy(0.2), decay = kDamping / (2 * kMass);
    const double omega_d = std::sqrt(kAnchorK[v] * kScale / kMass - decay * decay);
    const double settle_bound = kStopMs / 1000.0 + std::log(2 * speed / (omega_d * band)) / decay + 1.0 / kHz;
    EXPECT_LT(settle, settle_bound) << "vertex " << v;
    std::printf(", settling %.3f s (oracle %.3f s, envelope bound %.3f s)\n", settle,
                chain_settling(oracle, kHz, v, band), settle_bound);
  }
}

TEST(SkinDynamic, SameTrajectoryAt250HzAnd1kHz) {
  // The same motion ticked at 250 Hz and at 1 kHz with substep_hz 3500, so
  // the two rates integrate with different steps: ceil(3500 / 250) = 14
  // substeps of 1/3500 s, ceil(3500 / 1000) = 4 of 1/4000 s. Each run,
  // sampled at its ticks, lies within its own bound of the independent RK4
  // integration (FollowThroughMatchesAnIndependentIntegration's: symplectic
  // Euler's lag h |v|max, the implicit dashpots' decay change, under 1 % of
  // the follow-through swing over the run, and 16 LSB of rounding), so the two
  // trajectories agree within the sum wherever their ticks meet. Forcing
  // both rates onto one substep would test the rounding only.
  constexpr uint32_t kSubstep = 3500;
  constexpr double kSeconds = 1.5;
  double worst_pair = 0, pair_bound = 0;
  std::vector<std::array<double, kChain>> runs[2];
  const uint32_t rates[2] = {250, 1000};
  for (int r = 0; r < 2; ++r) {
    double max_speed = 0;
    const auto oracle = oracle_chain(rates[r], kSeconds, &max_speed);
    runs[r] = run_chain(rates[r], kSeconds, kSubstep);
    ASSERT_EQ(runs[r].size(), oracle.size());
    const uint32_t substeps = (kSubstep + rates[r] - 1) / rates[r];
    const double h = 1.0 / (static_cast<double>(rates[r]) * substeps);
    double swing = 0;  // the follow-through the dashpots damp
    for (int v = 0; v < kChain; ++v) swing = std::max(swing, chain_overshoot(oracle, rates[r], v));
    const double bound = max_speed * h + 0.01 * swing + 16.0 / 1048576.0;
    double worst = 0;
    for (size_t k = 0; k < oracle.size(); ++k)
      for (size_t v = 0; v < kChain; ++v) worst = std::max(worst, std::abs(runs[r][k][v] - oracle[k][v]));
    std::printf("%u Hz, %u substeps of %.3g s: largest |skin - RK4| %.3g units (bound %.3g)\n", rates[r], substeps, h,
                worst, bound);
    EXPECT_LE(worst, bound) << rates[r] << " Hz";
    pair_bound += bound;
  }
  ASSERT_EQ(runs[1].size(), 4 * (runs[0].size() - 1) + 1);
  for (size_t k = 0; k < runs[0].size(); ++k)
    for (size_t v = 0; v < kChain; ++v) worst_pair = std::max(worst_pair, std::abs(runs[0][k][v] - runs[1][4 * k][v]));
  std::printf("largest 250 Hz / 1 kHz difference: %.3g units (bound %.3g)\n", worst_pair, pair_bound);
  EXPECT_LE(worst_pair, pair_bound);
}

TEST(SkinDynamic, NoPointInsideAnActivePrimitiveAfterAStep) {
  // A ring of skin around a sphere of radius 0.2, fat 0.02; the bone drives
  // the anchors 0.15 into the sphere and back, fast.
  DynamicSkin s;
  constexpr int kRingCount = 16;
  for (int i = 0; i < kRingCount; ++i) {
    const double a = 2 * 3.141592653589793 * i / kRingCount;
    s.add_vertex(0.25 * std::cos(a), 0.25 * std::sin(a), 0, 2.0, 0.02);
  }
  for (int i = 0; i < kRingCount; ++i)
    s.add_edge(static_cast<uint32_t>(i), static_cast<uint32_t>((i + 1) % kRingCount), 1.0, 0.0975);
  s.add_sphere(0, 0, 0, 0.2);
  s.model.solver.gravity = {0, to_accel(-9.81), 0};
  ASSERT_TRUE(s.finish());
  const sinew::fx::Unit limit = sinew::fx::kUnitOne - (sinew::fx::kUnitOne >> 10);
  uint32_t pushed = 0;
  for (int k = 0; k < 400; ++k) {
    s.move_bone(0.15 * std::sin(k * 0.05), 0, 0);
    ASSERT_TRUE(s.step(1000).ok());
    pushed += s.state.stats.reactions;
    EXPECT_EQ(s.state.stats.inside_after, 0u) << "tick " << k;
    // Independent check of every fat point against the sphere's F.
    for (uint32_t v = 0; v < s.model.vertex_count; ++v) {
      const sinew::fx::Vec3 n{s.state.normal[0][v], s.state.normal[1][v], s.state.normal[2][v]};
      const double fat = 0.02;
      const double px = s.pos(0, v) - fat * n.x / 1073741824.0, py = s.pos(1, v) - fat * n.y / 1073741824.0,
                   pz = s.pos(2, v) - fat * n.z / 1073741824.0;
      const double f = (px * px + py * py + pz * pz) / (0.2 * 0.2);
      ASSERT_GE(f, double(limit) / 1073741824.0 - 1e-6) << "tick " << k << " vertex " << v;
    }
  }
  EXPECT_GT(pushed, 100u);  // the constraint did work
}

TEST(SkinDynamic, PointPushedAgainstAPrimitiveKeepsItsTangentialMotion) {
  // A free point (no springs, no dashpots) on top of a sphere of radius 1
  // centred at (0, -1, 0), under gravity into it, moving at 0.5 units/s
  // along x and 0.5 units/s into the sphere.
  DynamicSkin s;
  s.add_vertex(0, 0, 0, 0.0);
  s.add_sphere(0, -1, 0, 1.0);
  s.model.solver.anchor_damping = 0;
  s.model.solver.gravity = {0, to_accel(-9.81), 0};
  ASSERT_TRUE(s.finish());
  ASSERT_TRUE(s.step(1000).ok());  // starts at rest on its anchor
  s.state.velocity[0][0] = to_len(0.5);
  s.state.velocity[1][0] = to_len(-0.5);
  constexpr int kTicks = 100;  // 0.1 s: the point travels 0.05 units, 2.9 degrees of the sphere
  for (int k = 0; k < kTicks; ++k) ASSERT_TRUE(s.step(1000).ok());
  const double x = s.pos(0, 0), y = s.pos(1, 0);
  // On the surface (never inside, within the push-out's rounding).
  EXPECT_GE(std::hypot(x, y + 1.0), 1.0 - 1e-5);
  EXPECT_LE(std::hypot(x, y + 1.0), 1.0 + 1e-3);
  // The tangential motion is kept: over 0.1 s the point slides 0.05 units.
  // Gravity's tangential pull on a 2.9 degree arc (g sin(theta) < 0.5
  // units/s^2) changes that by less than 0.5 * 0.5 * 0.1^2 = 0.0025.
  EXPECT_NEAR(x, 0.05, 0.0025);
  // Only the inward normal velocity was removed: what is left inward is at
  // most what gravity adds in one substep (g h) when the last substep left
  // the point just outside, so no reaction ran.
  const double nx = x, ny = y + 1.0, nl = std::hypot(nx, ny);
  const double one_substep = 9.81 / s.model.solver.substep_hz;
  EXPECT_GE((s.vel(0, 0) * nx + s.vel(1, 0) * ny) / nl, -one_substep);
  EXPECT_NEAR(s.vel(0, 0), 0.5, 0.05);
}

TEST(SkinDynamic, RubberBandDampingDecaysTheOscillation) {
  // A point held only by a rubber band (k = 1 x 20 N/unit, m = 0.01 kg,
  // omega = 44.7 rad/s), released 0.1 units from the band's target.
  const auto amplitude_after = [](double band_damping) {
    DynamicSkin s;
    s.add_vertex(0.1, 0, 0, 0.0);
    s.add_band(0, 0, 1.0, 0, 0, 0);
    s.model.solver.stiffness_scale = to_q16(20.0);
    s.model.solver.anchor_damping = 0;
    s.model.solver.band_damping = to_q16(band_damping);
    EXPECT_TRUE(s.finish());
    // The first step settles the point on its target (the skin starts at
    // its equilibrium); then it is let go 0.1 units away, at rest.
    EXPECT_TRUE(s.step(1000).ok());
    s.state.position[0][0] = sinew::test::to_len(0.1);
    s.state.fine[0][0] = int64_t{s.state.position[0][0]} << 16;
    double worst = 0;
    for (int k = 1; k <= 1000; ++k) {  // 1 s
      EXPECT_TRUE(s.step(1000).ok());
      if (k >= 900) worst = std::max(worst, std::abs(s.pos(0, 0)));
    }
    return worst;
  };
  // c = 0.02 N s/unit: the envelope decays as exp(-c t / 2m) = exp(-t), so
  // the largest |x| over 0.9..1 s lies between 0.1 exp(-1) and
  // 0.1 exp(-0.9), up to what the integration changes (h = 1 ms, the
  // default substep_hz at 1 kHz; hw = 0.0447, hc/m = 0.002):
  //  - released at rest, the exact amplitude is the envelope / sqrt(1 - z^2)
  //    (z = c / (2 sqrt(k m)) = 0.0224);
  //  - symplectic Euler keeps w^2 x^2 - h w^2 x v + v^2, whose largest x is
  //    the start's / sqrt(1 - (hw)^2 / 4);
  //  - its implicit dashpot shrinks the invariant by 1 / (1 + hc/m) a step,
  //    against exp(-hc/m) exactly: the amplitude decays slower by at most
  //    exp(t/h (hc/m)^2 / 2) (the FollowThrough test's figure);
  //  - the ticks sample a peak at most half a step away: cos(hw / 2);
  //  - 16 LSB of fixed-point rounding.
  const double h = 1e-3, w = std::sqrt(20.0 / 0.01), hc_m = h * 0.02 / 0.01, z = 0.02 / (2 * std::sqrt(20.0 * 0.01));
  const double lsb16 = 16.0 / 1048576.0;
  const double above =
      1 / std::sqrt(1 - z * z) / std::sqrt(1 - h * h * w * w / 4) * std::exp(1.0 / h * hc_m * hc_m / 2);
  const double below = std::cos(h * w / 2);
  const double damped = amplitude_after(0.02);
  std::printf("rubber band, c = 0.02: largest |x| over 0.9..1 s %.6f in [%.6f, %.6f]\n", damped,
              0.1 * std::exp(-1.0) * below - lsb16, 0.1 * std::exp(-0.9) * above + lsb16);
  EXPECT_LT(damped, 0.1 * std::exp(-0.9) * above + lsb16);
  EXPECT_GT(damped, 0.1 * std::exp(-1.0) * below - lsb16);
  // Without the dashpot the oscillation keeps its amplitude (symplectic
  // Euler does not dissipate): the same sampling and rounding bound.
  EXPECT_GT(amplitude_after(0.0), 0.1 * below - lsb16);
}

TEST(SkinDynamic, FatKeepsTheSkinItsThicknessOutsideThePrimitive) {
  // Two points pulled into a sphere of radius 0.2 by their anchors (at
  // radius 0.1): one with its own fat 0.03, one with none; then a global
  // thickness of 0.02 is added to both.
  const auto radii = [](double global_fat) {
    DynamicSkin s;
    s.add_vertex(0.1, 0, 0, 2.0, 0.03);
    s.add_vertex(0, 0.1, 0, 2.0, 0.0);
    s.add_sphere(0, 0, 0, 0.2);
    s.model.solver.fat_thickness = to_len(global_fat);
    EXPECT_TRUE(s.finish());
    for (int k = 0; k < 500; ++k) EXPECT_TRUE(s.step(1000).ok());
    return std::array<double, 2>{std::hypot(s.pos(0, 0), s.pos(1, 0)), std::hypot(s.pos(0, 1), s.pos(1, 1))};
  };
  // The fat point (skin - fat along the outward normal) sits on the
  // sphere: the skin at 0.2 + fat (within the push-out's rounding, 1e-5).
  const auto own = radii(0.0);
  EXPECT_NEAR(own[0], 0.23, 1e-4);
  EXPECT_NEAR(own[1], 0.20, 1e-4);
  const auto both = radii(0.02);
  EXPECT_NEAR(both[0], 0.25, 1e-4);
  EXPECT_NEAR(both[1], 0.22, 1e-4);
}

TEST(SkinDynamic, GravitySagsTheSkinByMgOverK) {
  // One point on an anchor spring k = 1 x 50 N/unit, m = 0.01 kg: under g
  // = 9.81 it settles m g / k = 1.962 mm below its anchor; a base
  // accelerating upwards at 9.81 doubles the sag (the skin feels -a_base).
  DynamicSkin s;
  s.add_vertex(0, 0, 0, 1.0);
  s.model.solver.gravity = {0, to_accel(-9.81), 0};
  ASSERT_TRUE(s.finish());
  for (int k = 0; k < 2000; ++k) ASSERT_TRUE(s.step(1000).ok());
  EXPECT_NEAR(s.pos(1, 0), -0.01 * 9.81 / 50.0, 4e-6);
  for (int k = 0; k < 2000; ++k) ASSERT_TRUE(s.step(1000, {0, to_accel(9.81), 0}).ok());
  EXPECT_NEAR(s.pos(1, 0), -2 * 0.01 * 9.81 / 50.0, 4e-6);
}

TEST(SkinDynamic, RefusesTicksItCannotIntegrateStably) {
  DynamicSkin s;
  build_chain(&s);
  ASSERT_TRUE(s.finish());
  EXPECT_FALSE(s.step(0).ok());   // no time base
  EXPECT_FALSE(s.step(10).ok());  // 400 substeps > max_substeps 16
  EXPECT_TRUE(s.step(250).ok());
  EXPECT_EQ(es::skin_substeps(s.model.solver, 1000), 4u);
  EXPECT_EQ(es::skin_substeps(s.model.solver, 300), 14u);
  // omega_max^2 <= 6 x 1000 / 1e-4 = 6e7 /s^2 > H^2 = 1.6e7 at 1 kHz (4 substeps).
  s.model.solver.stiffness_scale = to_q16(1000.0);
  s.model.solver.vertex_mass = to_q24(1e-4);
  EXPECT_FALSE(s.step(1000).ok());
  s.model.solver.max_substeps = 64;
  s.model.solver.substep_hz = 16000;  // H^2 = 2.56e8 > 6e7: stable again
  EXPECT_TRUE(s.step(1000).ok());
}

TEST(SkinDynamic, StepsNeverTouchTheHeap) {
  DynamicSkin s;
  build_chain(&s);
  s.add_sphere(0.15, -0.3, 0, 0.25);
  ASSERT_TRUE(s.finish());
  ASSERT_TRUE(s.step(1000).ok());
  sinew::test::AllocationCounter counter;
  uint32_t failures = 0;
  for (int k = 0; k < 1000; ++k) {
    s.move_bone(0, -0.1 * std::sin(k * 0.01), 0);
    failures += !s.step(1000).ok();
  }
  EXPECT_EQ(failures, 0u);
  EXPECT_EQ(counter.allocations(), 0u);
}
