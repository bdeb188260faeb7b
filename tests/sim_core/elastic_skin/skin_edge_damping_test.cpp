// Edge dashpots of the dynamic skin (LEMAN §3: the surface's springs with
// damping): a two-vertex skin whose free vertex swings along its edge
// after the bone moves, against an independent double-precision RK4
// integration of the same spring-dashpot system; the dashpot shortens the
// settling, and its absence leaves the swing undamped.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "dynamic_skin_fixture.hpp"

using sinew::test::DynamicSkin;
using sinew::test::from_len;
using sinew::test::to_len;
using sinew::test::to_q16;
using sinew::test::to_q24;

namespace {

// Vertex 0 held by a stiff anchor at x = 0; vertex 1 on no anchor, joined
// to it by an edge of rest length 0.1 (20 N/unit); the bone moves along x
// at 512 LSB/ms from 0.1 s to 0.3 s. Mass 0.01 kg, no other damping.
constexpr double kEdgeDampRest = 0.1;
constexpr double kEdgeDampScale = 20.0;
constexpr double kEdgeDampAnchorK = 4.0;
constexpr double kEdgeDampEdgeK = 1.0;
constexpr double kEdgeDampMass = 0.01;
constexpr int kEdgeDampStartMs = 100, kEdgeDampStopMs = 300;
constexpr int64_t kEdgeDampLsbPerMs = 512;
constexpr uint32_t kEdgeDampSubstepHz = 4000;  // h = 1/4000 s, the bounds below

double edge_damp_bone_x(double t) {
  const double ms = std::clamp(t * 1000.0, double{kEdgeDampStartMs}, double{kEdgeDampStopMs}) - kEdgeDampStartMs;
  return from_len(kEdgeDampLsbPerMs) * ms;
}
double edge_damp_bone_vx(double t) {
  const double ms = t * 1000.0;
  return (ms >= kEdgeDampStartMs && ms < kEdgeDampStopMs) ? from_len(kEdgeDampLsbPerMs) * 1000.0 : 0.0;
}

// x of vertex 1 after each 1 kHz tick.
std::vector<double> edge_damp_run(double edge_damping, double seconds) {
  DynamicSkin s;
  s.add_vertex(0, 0, 0, kEdgeDampAnchorK);
  s.add_vertex(kEdgeDampRest, 0, 0, 0.0);
  s.add_edge(0, 1, kEdgeDampEdgeK, kEdgeDampRest);
  s.model.solver.stiffness_scale = to_q16(kEdgeDampScale);
  s.model.solver.vertex_mass = to_q24(kEdgeDampMass);
  s.model.solver.anchor_damping = 0;
  s.model.solver.band_damping = 0;
  s.model.solver.edge_damping = to_q16(edge_damping);
  s.model.solver.substep_hz = kEdgeDampSubstepHz;
  EXPECT_TRUE(s.finish());
  std::vector<double> out;
  const int ticks = static_cast<int>(std::lround(seconds * 1000));
  for (int k = 0; k <= ticks; ++k) {
    const int ms = std::clamp(k, kEdgeDampStartMs, kEdgeDampStopMs) - kEdgeDampStartMs;
    s.bone.t[0] = static_cast<sinew::fx::Len>(kEdgeDampLsbPerMs * ms);
    EXPECT_TRUE(s.step(1000).ok());
    out.push_back(s.pos(0, 1));
  }
  return out;
}

// The same system from the equations: x0, x1 along the edge (the motion
// stays on the x axis), anchor spring on x0, edge spring k (l - rest) and
// dashpot c (v1 - v0) along the edge; RK4 at 40 kHz.
std::vector<double> edge_damp_oracle(double c, double seconds, double* max_speed) {
  using S = std::array<double, 4>;  // x0, x1, v0, v1
  const double ka = kEdgeDampAnchorK * kEdgeDampScale, ke = kEdgeDampEdgeK * kEdgeDampScale, m = kEdgeDampMass;
  const auto deriv = [&](const S& s, double t) {
    const double edge = ke * (s[1] - s[0] - kEdgeDampRest) + c * (s[3] - s[2]);
    return S{s[2], s[3], (ka * (edge_damp_bone_x(t) - s[0]) + edge) / m, -edge / m};
  };
  S s{0, kEdgeDampRest, 0, 0};
  const double h = 1.0 / 40000.0;
  std::vector<double> out{s[1]};
  *max_speed = 0;
  const int ticks = static_cast<int>(std::lround(seconds * 1000));
  for (int k = 1; k <= ticks; ++k) {
    for (int j = 0; j < 40; ++j) {
      const double t = (k - 1) / 1000.0 + j * h;
      const S k1 = deriv(s, t);
      S a;
      for (int i = 0; i < 4; ++i)
        a[static_cast<size_t>(i)] = s[static_cast<size_t>(i)] + h / 2 * k1[static_cast<size_t>(i)];
      const S k2 = deriv(a, t + h / 2);
      for (int i = 0; i < 4; ++i)
        a[static_cast<size_t>(i)] = s[static_cast<size_t>(i)] + h / 2 * k2[static_cast<size_t>(i)];
      const S k3 = deriv(a, t + h / 2);
      for (int i = 0; i < 4; ++i)
        a[static_cast<size_t>(i)] = s[static_cast<size_t>(i)] + h * k3[static_cast<size_t>(i)];
      const S k4 = deriv(a, t + h);
      for (size_t i = 0; i < 4; ++i) s[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
      *max_speed = std::max({*max_speed, std::abs(s[2]), std::abs(s[3])});
    }
    out.push_back(s[1]);
  }
  return out;
}

// Last time (s) |x1 - final| exceeds `band`.
double edge_damp_settling(const std::vector<double>& x, double band) {
  const double final_x = edge_damp_bone_x(1e9) + kEdgeDampRest;
  double last = 0;
  for (size_t k = 0; k < x.size(); ++k)
    if (std::abs(x[k] - final_x) > band) last = double(k) / 1000.0;
  return last;
}

// When |x1 - final| stays below `band` for good, by the damping envelope of
// the two modes of K = [[ka + ke, -ke], [-ke, ke]] / m (x0, x1 along the
// edge). There is no dashpot but the edge's, so a bone at constant speed V
// leaves no lag: in the anchor's frame each of its two speed steps (start,
// stop) gives both vertices the velocity -V, which mode k (shape phi_k,
// frequency omega_k) carries to x1 with amplitude
// |phi_k1 (phi_k . (1, 1))| V / (|phi_k|^2 omega_k); it decays at
// sigma_k = c (phi_k1 - phi_k0)^2 / (2 m |phi_k|^2) (modal damping: at
// damping ratios below 0.04 the dashpot's coupling of the modes moves the
// rates by O(zeta^2)). Both steps' amplitudes, all decaying at the slowest
// rate from the stop: t_stop + ln(A / band) / sigma_min, plus one 1 ms tick
// of sampling.
double edge_damp_settling_bound(double c, double band) {
  const double m = kEdgeDampMass, ka = kEdgeDampAnchorK * kEdgeDampScale, ke = kEdgeDampEdgeK * kEdgeDampScale;
  const double a = ka + ke, d = ke;  // K = [[a, -ke], [-ke, d]]
  const double mean = (a + d) / 2, half = std::sqrt((a - d) * (a - d) / 4 + ke * ke);
  const double speed = edge_damp_bone_vx(0.2);
  double amplitude = 0, sigma_min = 1e300;
  for (const double lambda : {mean - half, mean + half}) {
    const double phi0 = ke, phi1 = a - lambda;  // (K - lambda) phi = 0, first row
    const double norm2 = phi0 * phi0 + phi1 * phi1;
    amplitude += 2 * std::abs(phi1 * (phi0 + phi1)) * speed / (norm2 * std::sqrt(lambda / m));
    sigma_min = std::min(sigma_min, c * (phi1 - phi0) * (phi1 - phi0) / (2 * m * norm2));
  }
  return kEdgeDampStopMs / 1000.0 + std::log(amplitude / band) / sigma_min + 0.001;
}

}  // namespace

TEST(SkinEdgeDamping, EdgeDashpotShortensSettlingLikeTheIndependentIntegration) {
  constexpr double kSeconds = 3.0;
  constexpr double kC = 0.05;                      // N s per unit: the relative mode decays at about c / 2m = 2.5 / s
  const double amplitude = edge_damp_bone_x(1e9);  // 0.09765625 units
  const double band = 0.01 * amplitude;
  double speed_damped = 0, speed_free = 0;
  const auto oracle_damped = edge_damp_oracle(kC, kSeconds, &speed_damped);
  const auto oracle_free = edge_damp_oracle(0.0, kSeconds, &speed_free);
  const auto damped = edge_damp_run(kC, kSeconds);
  const auto free_swing = edge_damp_run(0.0, kSeconds);
  ASSERT_EQ(damped.size(), oracle_damped.size());
  // Trajectories: symplectic Euler (h = 1/4000 s) lags the exact one by at
  // most h |v|max, plus the explicit dashpot's O(h c / m) = 1.25 % of the
  // swing and 16 LSB of rounding.
  double worst_damped = 0, worst_free = 0;
  for (size_t k = 0; k < damped.size(); ++k) {
    worst_damped = std::max(worst_damped, std::abs(damped[k] - oracle_damped[k]));
    worst_free = std::max(worst_free, std::abs(free_swing[k] - oracle_free[k]));
  }
  const double swing = 0.02;  // the free vertex's lag: |v| / omega = 0.49 / 44.7 < 0.011, doubled
  std::printf("largest |skin - oracle|: damped %.3g, undamped %.3g units (bounds %.3g, %.3g)\n", worst_damped,
              worst_free, speed_damped / kEdgeDampSubstepHz + 0.0125 * swing + 16.0 / 1048576.0,
              speed_free / kEdgeDampSubstepHz + 2e-5 + 16.0 / 1048576.0);
  EXPECT_LE(worst_damped, speed_damped / kEdgeDampSubstepHz + 0.0125 * swing + 16.0 / 1048576.0);
  // Without the dashpot the phase error of symplectic Euler accumulates
  // over the undamped swing: (h omega)^2 / 24 = 5.2e-6 per radian; 3 s at
  // 44.7 rad/s shift the phase by 7e-4 rad, i.e. 8e-6 units of the 0.011
  // swing (2e-5 allowed).
  EXPECT_LE(worst_free, speed_free / kEdgeDampSubstepHz + 2e-5 + 16.0 / 1048576.0);
  const double settle_damped = edge_damp_settling(damped, band), settle_free = edge_damp_settling(free_swing, band);
  const double oracle_settle_damped = edge_damp_settling(oracle_damped, band);
  std::printf(
      "settling into 1%% of the motion: %.3f s with the edge dashpot (oracle %.3f s), %.3f s without (oracle "
      "%.3f s)\n",
      settle_damped, oracle_settle_damped, settle_free, edge_damp_settling(oracle_free, band));
  // The physics: with the dashpot the swing dies out within its damping
  // envelope, without it the swing never settles.
  const double settle_bound = edge_damp_settling_bound(kC, band);
  std::printf("envelope bound on the settling with the edge dashpot: %.3f s\n", settle_bound);
  EXPECT_LT(settle_damped, settle_bound);
  EXPECT_GT(settle_free, settle_bound);
  EXPECT_GE(settle_free, kSeconds - 0.1);
  // Within the oracle's settling for bands 10 % wider and narrower.
  EXPECT_GE(settle_damped, edge_damp_settling(oracle_damped, 1.1 * band) - 0.001);
  EXPECT_LE(settle_damped, edge_damp_settling(oracle_damped, 0.9 * band) + 0.001);
}

TEST(SkinEdgeDamping, RefusesDashpotsTooStiffForTheSubstep) {
  // 2 c degree / m must stay below the substep rate: c = 30 N s/unit on a
  // vertex of degree 1, m = 0.01 kg gives 6000/s > 4000/s.
  DynamicSkin s;
  s.add_vertex(0, 0, 0, 1.0);
  s.add_vertex(0.1, 0, 0, 1.0);
  s.add_edge(0, 1, 1.0, 0.1);
  s.model.solver.edge_damping = to_q16(30.0);
  s.model.solver.substep_hz = kEdgeDampSubstepHz;
  ASSERT_TRUE(s.finish());
  const auto st = s.step(1000);
  EXPECT_FALSE(st.ok());
  std::printf("refused: %s\n", st.message);
  s.model.solver.edge_damping = to_q16(15.0);  // 3000/s: accepted
  EXPECT_TRUE(s.step(1000).ok());
}
