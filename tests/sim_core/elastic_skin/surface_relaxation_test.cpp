// LEMAN's elastic surface advanced by §6.11's relaxation
// (sim_core/elastic_skin/surface_relaxation.hpp), against double-precision
// oracles written from the equations: the step itself (stretch, bend,
// bands, gravity, air pressure, Platt-Barr reactions), the energy the bend
// term descends, Laplace's law for the inflated surface, the critically
// damped reaction law, and the relaxation's damping.
#include "sim_core/elastic_skin/surface_relaxation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "tests/sim_core/elastic_skin/dynamic_skin_fixture.hpp"
#include "tests/sim_core/elastic_skin/relaxation_oracle.hpp"
#include "tests/sim_core/muscle/anatomy_fixture.hpp"

namespace es = sinew::elastic_skin;
using sinew::test::DynamicSkin;
using sinew::test::from_len;
using sinew::test::to_len;
using sinew::test::to_q16;

namespace {

constexpr double kLsb = 1.0 / 1048576.0;  // one Len LSB, rig units

void use_relaxation(DynamicSkin* s, double bend, double pressure, double reaction_hz, int sweeps) {
  s->model.surface.integrator = static_cast<uint8_t>(es::SkinIntegrator::kRelaxation);
  s->model.surface.relaxation_iterations = static_cast<uint8_t>(sweeps);
  s->model.surface.bend = static_cast<es::Stiffness>(to_q16(bend));
  s->model.surface.pressure = to_q16(pressure);
  s->model.surface.reaction_frequency = to_q16(reaction_hz);
}

// A square sheet of side `count` vertices, spacing 1, in the plane y =
// height, two triangles per cell; edges along the grid and one diagonal.
struct Sheet {
  uint32_t count = 0;
  uint32_t at(uint32_t i, uint32_t j) const { return i * count + j; }
};
Sheet add_sheet(DynamicSkin* s, uint32_t count, double height, double anchor_k, double edge_k, double spacing = 1.0) {
  Sheet sheet{count};
  const double half = (count - 1) * spacing / 2;
  for (uint32_t i = 0; i < count; ++i)
    for (uint32_t j = 0; j < count; ++j)
      s->add_vertex_with_normal(i * spacing - half, height, j * spacing - half, 0, 1, 0, anchor_k);
  for (uint32_t i = 0; i < count; ++i)
    for (uint32_t j = 0; j < count; ++j) {
      if (i + 1 < count) s->add_edge(sheet.at(i, j), sheet.at(i + 1, j), edge_k, spacing);
      if (j + 1 < count) s->add_edge(sheet.at(i, j), sheet.at(i, j + 1), edge_k, spacing);
      if (i + 1 < count && j + 1 < count) {
        s->add_edge(sheet.at(i, j), sheet.at(i + 1, j + 1), edge_k, spacing * std::sqrt(2.0));
        s->add_triangle(sheet.at(i, j), sheet.at(i + 1, j), sheet.at(i + 1, j + 1));
        s->add_triangle(sheet.at(i, j), sheet.at(i + 1, j + 1), sheet.at(i, j + 1));
      }
    }
  return sheet;
}

using sinew::test::OraclePrimitive;
using sinew::test::RelaxationOracle;
using sinew::test::V3;
V3 sub(const V3& a, const V3& b) { return sinew::test::sub3(a, b); }
double dot(const V3& a, const V3& b) { return sinew::test::dot3(a, b); }
double norm(const V3& a) { return sinew::test::norm3(a); }

// The fixture's inputs to the oracle: anchors on the one bone at `bone`,
// their rest normals, the bands' fixed targets, its spheres.
struct FixtureInputs {
  std::vector<V3> anchors, normals, targets;
  std::vector<OraclePrimitive> prims;
};
FixtureInputs inputs_of(const DynamicSkin& s, const V3& bone) {
  FixtureInputs in;
  for (const es::Anchor& a : s.anchors) {
    in.anchors.push_back(
        {from_len(a.local_a.x) + bone[0], from_len(a.local_a.y) + bone[1], from_len(a.local_a.z) + bone[2]});
    in.normals.push_back(sinew::test::unit_of(a.normal_a));
  }
  for (const es::RubberBand& b : s.bands) {
    const sinew::fx::Vec3 t = s.band_target[b.ring_vertex];
    in.targets.push_back({from_len(t.x), from_len(t.y), from_len(t.z)});
  }
  for (const auto& f : s.frames) {
    OraclePrimitive p;
    p.centre = {from_len(f.centre.x), from_len(f.centre.y), from_len(f.centre.z)};
    for (int i = 0; i < 3; ++i) p.axis[i] = sinew::test::unit_of(f.axis[i]), p.extent[i] = from_len(f.extent[i]);
    p.exponent = 2;
    in.prims.push_back(p);
  }
  return in;
}
size_t oracle_step(RelaxationOracle* o, const DynamicSkin& s, double h, const V3& bone) {
  const FixtureInputs in = inputs_of(s, bone);
  return o->step(h, in.anchors, in.normals, in.targets, in.prims);
}
// The umbrella vectors L(x - a) of positions x over anchors a.
std::vector<V3> umbrella_of(RelaxationOracle o, const std::vector<V3>& x, const std::vector<V3>& a) {
  o.x = x;
  return o.umbrella(a);
}

double largest_gap(const DynamicSkin& s, const RelaxationOracle& o) {
  double worst = 0;
  for (size_t i = 0; i < o.n; ++i) {
    V3 d{};
    for (int c = 0; c < 3; ++c) d[c] = s.pos(c, uint32_t(i)) - o.x[i][c];
    worst = std::max(worst, norm(d));
  }
  return worst;
}

}  // namespace

// A 5 x 5 sheet over a sphere it presses into, its anchors swept sideways
// and back, with stretch, bend, a rubber band, gravity and air pressure:
// the runtime's trajectory against the oracle's, step for step.
TEST(SurfaceRelaxation, StepsLikeADoubleOracleOfTheEquationOfMotion) {
  for (const uint32_t tick_hz : {100u, 1000u}) {
    DynamicSkin s;
    const Sheet sheet = add_sheet(&s, 5, 0.0, 0.5, 2.0);
    s.add_band(sheet.at(2, 2), 0, 1.0, 0.0, 0.3, 0.0);
    s.add_sphere(0.3, -1.6, 0.2, 1.8);  // its top 0.2 above the sheet: the middle presses into it
    s.model.solver.gravity = {0, sinew::test::to_accel(-9.81), 0};
    s.model.solver.vertex_mass = sinew::test::to_q24(0.02);
    use_relaxation(&s, 1.5, 3.0, 40.0, 3);
    ASSERT_TRUE(s.finish());
    const sinew::muscle::LayerStatus first = s.step(tick_hz);  // settles at rest on the first pose
    ASSERT_TRUE(first.ok()) << first.message;
    RelaxationOracle o(s.model);
    o.start(s.state);
    const int ticks = int(tick_hz / 2);  // half a second
    double worst = 0, moved = 0;
    uint32_t reacting = 0;
    for (int k = 1; k <= ticks; ++k) {
      const double t = double(k) / tick_hz;
      const V3 bone{0.4 * std::sin(2 * M_PI * 2 * t), 0.1 * std::sin(2 * M_PI * 3 * t), 0};
      s.move_bone(bone[0], bone[1], bone[2]);
      ASSERT_TRUE(s.step(tick_hz).ok());
      // The oracle takes the anchors the runtime rounded.
      oracle_step(&o, s, 1.0 / tick_hz, {from_len(to_len(bone[0])), from_len(to_len(bone[1])), 0});
      worst = std::max(worst, largest_gap(s, o));
      reacting += s.state.stats.reactions;
      for (size_t i = 0; i < o.n; ++i) moved = std::max(moved, std::fabs(o.x[i][1]));
    }
    // The bound, from the rounding: each move reads its neighbours' Len
    // positions (rounded by half an LSB; the spring and bend weights sum to
    // less than the row's diagonal, so the move errs by at most half an LSB
    // a sweep), and the reaction's normal is Q2.30 (2^-30 of the floor's
    // distance, far below an LSB here). Carried between steps through x
    // and x - x0, an error is damped by the dashpots but can be held by the
    // springs: at most one LSB a step accumulates, so 1 LSB x sweeps x
    // ticks bounds the gap, a bound the steps' own scale (up to 0.5 units)
    // dwarfs.
    const double bound = 1.0 * o.sweeps * ticks * kLsb;
    std::printf("%u Hz: %d steps, %u reactions, largest |y| %.3f, largest gap %.3g units (bound %.3g)\n", tick_hz,
                ticks, reacting, moved, worst, bound);
    EXPECT_GT(reacting, 0u) << "the sheet must press into the sphere";
    EXPECT_LE(worst, bound);
  }
}

// §3 via Platt and Barr: a skin point whose anchor lies inside a large
// sphere rests on its surface; the sphere grows by 2 cm at once. The
// penetration must then follow backward Euler's discretisation of
// e'' + 2 w e' + w^2 e = 0 step for step (the floor binds: the anchor pulls
// inward), never overshoot, and the point's tangential motion must be the
// one it has with no sphere at all.
TEST(SurfaceRelaxation, ReactionReturnsCriticallyDampedAndLeavesTheTangentAlone) {
  constexpr uint32_t kHz = 1000;
  constexpr double kRadius = 1000, kGrowth = 0.02, kReactionHz = 30;
  DynamicSkin with, without;
  for (DynamicSkin* s : {&with, &without}) {
    s->add_vertex_with_normal(0, -0.05, 0, 0, 1, 0, 0.5);
    s->model.solver.vertex_mass = sinew::test::to_q24(0.02);
    use_relaxation(s, 0, 0, kReactionHz, 3);
  }
  with.add_sphere(0, -kRadius, 0, kRadius);
  ASSERT_TRUE(with.finish());
  ASSERT_TRUE(without.finish());
  const auto bone_x = [](int k) { return 0.05 * std::sin(2 * M_PI * k / 400.0); };
  double radius = kRadius;
  const auto penetration = [&] { return radius - std::hypot(with.pos(0, 0), with.pos(1, 0) + kRadius); };
  for (int k = 0; k < 300; ++k) {  // settles on the surface while sliding
    for (DynamicSkin* s : {&with, &without}) {
      s->move_bone(bone_x(k), 0, 0);
      ASSERT_TRUE(s->step(kHz).ok());
    }
  }
  // Resting contact: the inside test runs once a step, at the prediction
  // (§6.11), so a point pulled in (the anchor 5 cm inside: a = k d / m) is
  // caught a step late and enters at the speed h a it gained; the law then
  // returns it, its penetration peaking at (h a) / (w e) (the critically
  // damped response to a velocity, t e^(-w t) at t = 1 / w), plus the step
  // h^2 a it fell.
  const double h = 1.0 / kHz, omega = 2 * M_PI * kReactionHz, oh = omega * h;
  const double pull = 0.5 * 50 * (0.05 + kGrowth) / 0.02;  // k_a d / m, rig units / s^2
  const double resting = h * pull / (omega * std::exp(1.0)) + h * h * pull + 4 * kLsb;
  const double rest_before = penetration();
  EXPECT_LT(std::fabs(rest_before), resting) << "at rest on the surface";
  for (int c = 0; c < 3; ++c) with.frames[0].extent[c] = to_len(kRadius + kGrowth);
  radius = kRadius + kGrowth;
  double e = penetration(), rate = -with.vel(1, 0);  // the law's state: e, de/dt (the normal is +y within 5e-5)
  double worst = 0, lowest = 1, tangential = 0, lift_sum = 0, last = e;
  bool monotone = true;
  int compared = 0;
  for (int k = 300; k < 600; ++k) {
    for (DynamicSkin* s : {&with, &without}) {
      s->move_bone(bone_x(k), 0, 0);
      ASSERT_TRUE(s->step(kHz).ok());
    }
    // Backward Euler: rate' = (rate - w^2 h e) / (1 + w h)^2, e' = e + h rate'.
    rate = (rate - oh * oh / h * e) / ((1 + oh) * (1 + oh));
    e += h * rate;
    const double got = penetration();
    if (e > 2 * resting) {  // beyond that the resting contact's cycle takes over
      worst = std::max(worst, std::fabs(got - e));
      monotone = monotone && got <= last + 2 * kLsb;
      ++compared;
    }
    lowest = std::min(lowest, got);
    last = got;
    tangential = std::max(tangential, std::fabs(with.pos(0, 0) - without.pos(0, 0)));
    lift_sum += std::max(0.0, got);
  }
  // Bounds: the law against the runtime, a few LSB of rounding a step
  // (positions, the Q2.30 normal) over a response whose L1 gain is at most
  // 1 (critically damped, no overshoot): 4 LSB. The tangent: the reaction
  // moves the point along the sphere's normal only, whose x component is
  // x / R <= 0.05 / 1000, so the tangential paths part by at most that
  // times the sum of the lifts (each at most the penetration left).
  const double tangent_bound = 0.05 / kRadius * (lift_sum + kGrowth) + 4 * kLsb;
  std::printf(
      "reaction at %.0f Hz, w h = %.3f: resting penetration %.3g (bound %.3g); after the growth %d steps "
      "compared, worst |e - law| %.3g (bound %.3g), lowest e %.3g, last %.3g; tangential gap %.3g (bound %.3g)\n",
      kReactionHz, oh, rest_before, resting, compared, worst, 4 * kLsb, lowest, last, tangential, tangent_bound);
  EXPECT_GE(compared, 10);
  EXPECT_LE(worst, 4 * kLsb);
  EXPECT_TRUE(monotone) << "the penetration never grows back";
  EXPECT_GE(lowest, -4 * kLsb) << "the point never overshoots out of contact";
  EXPECT_LT(last, resting) << "300 ms = 57 / w: the law has long since returned it to resting contact";
  EXPECT_LE(tangential, tangent_bound);
}

// §5.3 air pressure: a regular icosahedron of springs at rest length,
// inflated by a uniform pressure P, settles at the radius where each
// vertex's five springs balance a third of its five faces' pressure force:
//   5 k (a R - L) a / 2 = P (5/3) (sqrt(3)/4) (a R)^2 rho
// (a = edge / circumradius, rho = inradius / circumradius). Solved in double.
TEST(SurfaceRelaxation, AirPressureInflatesAnIcosahedronToItsBalanceRadius) {
  constexpr double kRadius0 = 1.0, kPressure = 10.0, kEdgeModel = 1.0;
  const double phi = (1 + std::sqrt(5.0)) / 2;
  std::vector<V3> corners;
  for (double s1 : {-1.0, 1.0})
    for (double s2 : {-1.0, 1.0}) {
      corners.push_back({0, s1, s2 * phi});
      corners.push_back({s1, s2 * phi, 0});
      corners.push_back({s2 * phi, 0, s1});
    }
  const double scale = kRadius0 / std::sqrt(1 + phi * phi);
  for (V3& c : corners)
    for (double& x : c) x *= scale;
  const double edge = 2 * scale;
  DynamicSkin s;
  for (const V3& c : corners) s.add_vertex(c[0], c[1], c[2], 0.0);
  for (uint32_t i = 0; i < 12; ++i)
    for (uint32_t j = i + 1; j < 12; ++j)
      if (std::fabs(norm(sub(corners[i], corners[j])) - edge) < 1e-9) s.add_edge(i, j, kEdgeModel, edge);
  for (uint32_t i = 0; i < 12; ++i)
    for (uint32_t j = i + 1; j < 12; ++j)
      for (uint32_t k = j + 1; k < 12; ++k)
        if (std::fabs(norm(sub(corners[i], corners[j])) - edge) < 1e-9 &&
            std::fabs(norm(sub(corners[j], corners[k])) - edge) < 1e-9 &&
            std::fabs(norm(sub(corners[i], corners[k])) - edge) < 1e-9)
          s.add_triangle(i, j, k);
  ASSERT_EQ(s.edges.size(), 30u);
  ASSERT_EQ(s.triangles.size(), 60u);
  use_relaxation(&s, 0, kPressure, 100, 3);
  ASSERT_TRUE(s.finish());
  for (int k = 0; k < 2000; ++k) ASSERT_TRUE(s.step(1000).ok());
  const double k_spring = kEdgeModel * std::ldexp(double(s.model.solver.stiffness_scale), -16);
  const double a = 1.0514622242382672, rho = 0.7946544722917661;
  const double pressure = std::ldexp(double(s.model.surface.pressure), -16);
  // f(R) = springs - pressure, increasing through the root above R0.
  const auto f = [&](double r) {
    return 5 * k_spring * (a * r - edge) * a / 2 - pressure * 5.0 / 3 * std::sqrt(3.0) / 4 * (a * r) * (a * r) * rho;
  };
  double lo = kRadius0, hi = 2 * kRadius0;
  for (int i = 0; i < 200; ++i) (f((lo + hi) / 2) < 0 ? lo : hi) = (lo + hi) / 2;
  const double want = lo;
  // Radii from the centroid: with no anchor springs the ball may drift as a
  // whole (a free mode, damped only by the dashpots).
  V3 centre{};
  for (uint32_t i = 0; i < 12; ++i)
    for (int c = 0; c < 3; ++c) centre[c] += s.pos(c, i) / 12;
  double worst = 0, speed = 0;
  for (uint32_t i = 0; i < 12; ++i) {
    const V3 p{s.pos(0, i) - centre[0], s.pos(1, i) - centre[1], s.pos(2, i) - centre[2]};
    worst = std::max(worst, std::fabs(norm(p) - want));
    speed = std::max(speed, std::fabs(s.vel(0, i)) + std::fabs(s.vel(1, i)) + std::fabs(s.vel(2, i)));
  }
  // Bound: the positions' rounding (a few LSB) and the pressure gain's:
  // h^2 P / (6 m) in Q30 is 1.7e-4 here, kept to 2^-30 / 1.7e-4 = 5e-6 of
  // itself, which moves the balance radius by that fraction of the
  // inflation; plus what is left of the motion after 2 s (the dashpots
  // damp at c / m = 50 /s: e^-100).
  const double bound = 8 * kLsb + 5e-6 * (want - kRadius0);
  std::printf("icosahedron at P = %.1f: radius %.6f -> %.6f (balance), worst |r - R| %.3g (bound %.3g), speed %.3g\n",
              pressure, kRadius0, want, worst, bound, speed);
  EXPECT_GT(want - kRadius0, 0.01) << "the pressure must inflate it measurably";
  EXPECT_LE(worst, bound);
}

// The bend term is the descent of Terzopoulos' second-order energy
// 1/2 k_b sum_i |L(x - a)_i|^2: checked against central differences of
// that energy (not of the force formula), and the runtime's settled sheet,
// pulled up at one vertex, sits where the whole energy is stationary.
TEST(SurfaceRelaxation, BendDescendsTheSecondOrderEnergyAndTheSkinRestsAtItsMinimum) {
  DynamicSkin s;
  const Sheet sheet = add_sheet(&s, 4, 0.0, 0.3, 1.0);
  s.add_band(sheet.at(1, 2), 0, 2.0, -0.5, 0.6, 0.5);
  use_relaxation(&s, 2.0, 0, 100, 3);
  ASSERT_TRUE(s.finish());
  for (int k = 0; k < 3000; ++k) ASSERT_TRUE(s.step(1000).ok());
  RelaxationOracle o(s.model);
  o.start(s.state);
  const FixtureInputs in = inputs_of(s, {0, 0, 0});
  const std::vector<V3>& a = in.anchors;
  const auto energy = [&](const std::vector<V3>& x) {
    double e = 0;
    for (size_t i = 0; i < o.n; ++i) e += 0.5 * o.anchor_k[i] * dot(sub(x[i], a[i]), sub(x[i], a[i]));
    for (size_t k = 0; k < o.ea.size(); ++k) {
      const double d = norm(sub(x[o.eb[k]], x[o.ea[k]])) - o.erest[k];
      e += 0.5 * o.ek[k] * d * d;
    }
    for (size_t b = 0; b < o.band_vertex.size(); ++b) {
      const V3 d = sub(x[o.band_vertex[b]], in.targets[b]);
      e += 0.5 * o.band_k[b] * dot(d, d);
    }
    for (const V3& u : umbrella_of(o, x, a)) e += 0.5 * o.bend * dot(u, u);
    return e;
  };
  // (1) the bend force of the oracle (and the runtime) against -dE/dx of the
  // bend energy alone, by central differences, at a scrambled sheet.
  std::vector<V3> x = o.x;
  for (size_t i = 0; i < o.n; ++i)
    for (int c = 0; c < 3; ++c) x[i][c] += 0.05 * std::sin(7.0 * double(i) + 3.0 * c);
  const std::vector<V3> u = umbrella_of(o, x, a);
  double force_gap = 0, force_scale = 0;
  for (size_t i = 0; i < o.n; ++i)
    for (int c = 0; c < 3; ++c) {
      double formula = o.bend * u[i][c];
      for (uint32_t e : o.incident[i]) formula -= o.bend * u[o.other(e, i)][c] / o.degree(o.other(e, i));
      const double step = 1e-6;
      std::vector<V3> up = x, down = x;
      up[i][c] += step, down[i][c] -= step;
      double bend_up = 0, bend_down = 0;
      for (const V3& w : umbrella_of(o, up, a)) bend_up += 0.5 * o.bend * dot(w, w);
      for (const V3& w : umbrella_of(o, down, a)) bend_down += 0.5 * o.bend * dot(w, w);
      const double numeric = -(bend_up - bend_down) / (2 * step);
      force_gap = std::max(force_gap, std::fabs(formula - numeric));
      force_scale = std::max(force_scale, std::fabs(numeric));
    }
  EXPECT_LT(force_gap, 1e-6 * force_scale) << "the bend force is -grad of the bend energy";
  // (2) at the runtime's rest the whole energy is stationary: its gradient
  // (central differences) is what a displacement of a few LSB makes of it,
  // against the band's pull it balances.
  double gradient = 0;
  for (size_t i = 0; i < o.n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double step = 1e-6;
      std::vector<V3> up = o.x, down = o.x;
      up[i][c] += step, down[i][c] -= step;
      gradient = std::max(gradient, std::fabs(energy(up) - energy(down)) / (2 * step));
    }
  double pull = 0, stiffest = 0;
  for (size_t b = 0; b < o.band_vertex.size(); ++b)
    pull = std::max(pull, o.band_k[b] * norm(sub(o.x[o.band_vertex[b]], in.targets[b])));
  for (size_t i = 0; i < o.n; ++i) {
    double row = o.anchor_k[i] + o.bend * 3;
    for (size_t k = 0; k < o.ea.size(); ++k) row += (o.ea[k] == i || o.eb[k] == i) ? 2 * o.ek[k] : 0;
    stiffest = std::max(stiffest, row);
  }
  // A residual displacement of 16 LSB at the stiffest row.
  const double bound = 16 * kLsb * stiffest;
  std::printf("bend: force vs -dE/dx %.3g of %.3g; at rest |dE/dx| %.3g N (bound %.3g), band pull %.3g N\n", force_gap,
              force_scale, gradient, bound, pull);
  EXPECT_LE(gradient, bound);
  EXPECT_GT(pull, 100 * bound) << "the rest must be a balance of real forces";
  // And the bend shapes it: without it the same sheet rests elsewhere.
  DynamicSkin flat;
  const Sheet f = add_sheet(&flat, 4, 0.0, 0.3, 1.0);
  flat.add_band(f.at(1, 2), 0, 2.0, -0.5, 0.6, 0.5);
  use_relaxation(&flat, 0, 0, 100, 3);
  ASSERT_TRUE(flat.finish());
  for (int k = 0; k < 3000; ++k) ASSERT_TRUE(flat.step(1000).ok());
  double apart = 0;
  for (uint32_t i = 0; i < o.n; ++i) apart = std::max(apart, std::fabs(flat.pos(1, i) - s.pos(1, i)));
  EXPECT_GT(apart, 1000 * kLsb) << "the bend term must change the rest shape";
}

// §6.11's few sweeps a step: a sheet whose anchors jump 0.2 at 100 Hz,
// where its edge modes have h omega ~ 4 (explicit Euler would diverge: it
// needs h omega < 2), swings past its new rest by less than the jump and
// settles, with 1, 2 and 8 sweeps; and, as §6.11 says, the fewer the
// sweeps the more the partial solve damps.
TEST(SurfaceRelaxation, EverySweepCountIsStableWhereExplicitStepsDiverge) {
  const int sweeps[3] = {1, 2, 8};
  double overshoot[3] = {};
  for (int r = 0; r < 3; ++r) {
    DynamicSkin s;
    add_sheet(&s, 5, 0.0, 0.5, 4.0);
    s.model.solver.anchor_damping = 0;  // no dashpot: only the integrator damps
    use_relaxation(&s, 0.5, 0, 100, sweeps[r]);
    ASSERT_TRUE(s.finish());
    ASSERT_TRUE(s.step(100).ok());
    // The stiffest row's h omega (Gershgorin, as the explicit integrator's
    // check): 4 edges of 4 x 50 N/u a side at most, plus the anchor, over
    // 0.01 kg.
    const double omega = std::sqrt((0.5 + 2 * 8 * 4.0) * 50 / 0.01);
    s.move_bone(0, 0.2, 0);
    double peak = 0, late = 0;
    for (int k = 0; k < 1000; ++k) {
      ASSERT_TRUE(s.step(100).ok());
      peak = std::max(peak, s.pos(1, 12) - 0.2);
      if (k >= 900) late = std::max(late, std::fabs(s.pos(1, 12) - 0.2));
    }
    overshoot[r] = peak;
    std::printf("%d sweeps at 100 Hz (h omega_max %.1f): overshoot %.4g of the 0.2 jump, last second within %.3g\n",
                sweeps[r], omega / 100, peak, late);
    EXPECT_GT(omega / 100, 2.0) << "a regime explicit steps cannot take";
    EXPECT_LT(peak, 0.2) << sweeps[r] << " sweeps: no energy gained";
    EXPECT_LT(late, 0.01 * 0.2) << sweeps[r] << " sweeps: the swing dies out";
  }
  // §6.11: "the resulting error in the solution manifests itself as damping".
  EXPECT_LT(overshoot[0], overshoot[1]);
  EXPECT_LT(overshoot[1], overshoot[2]);
}

// The built-in arm with LEMAN's skin as the builder makes it by default
// (relaxation, bend, reactions on the two primitives), the elbow flexed 0 ->
// 90 degrees in 0.3 s and held, at 100 Hz and at 1 kHz: one implicit step a
// tick either way. The skin stays on the limb, and both rates settle to the
// same rest (the equilibrium does not depend on the step).
TEST(SurfaceRelaxationArm, FlexesAndSettlesAt100HzAnd1kHzWithItsPrimitives) {
  std::vector<double> rest[2];
  double limb_gap[2] = {}, contact = 0;
  const uint32_t rates[2] = {100, 1000};
  for (int r = 0; r < 2; ++r) {
    sinew::test::ArmAnatomy arm([](sinew::anatomy_build::AnatomySpec& s) { s.skin.solver.dynamic = true; });
    ASSERT_TRUE(arm.ok()) << arm.error();
    ASSERT_EQ(arm.skin_model().surface.integrator, static_cast<uint8_t>(es::SkinIntegrator::kRelaxation));
    uint32_t active = 0;
    for (const auto& p : arm.model().primitives) active += p.active != 0;
    ASSERT_GT(active, 0u);
    const uint32_t hz = rates[r];
    const int flex = int(hz * 3 / 10), hold = int(hz * 3 / 2);
    uint32_t reactions = 0;
    for (int k = 0; k <= flex + hold; ++k) {
      arm.set("elbow.0", 90.0 * std::min(k, flex) / flex);
      ASSERT_TRUE(arm.step_muscles().ok());
      const sinew::muscle::LayerStatus st = es::skin_step(arm.skin_model(), arm.muscle_model(), arm.muscles(),
                                                          arm.engine().model, es::SkinTick{hz, {}}, &arm.skin());
      ASSERT_TRUE(st.ok()) << st.message;
      reactions += arm.skin().stats.reactions;
      for (uint32_t v = 0; v < arm.skin_model().vertex_count; ++v) {
        double d2 = 0;
        for (int c = 0; c < 3; ++c) {
          const double d = arm.skin_pos(c, v) - arm.metres(arm.skin().anchor[c][v]);
          d2 += d * d;
        }
        limb_gap[r] = std::max(limb_gap[r], std::sqrt(d2));
      }
    }
    for (uint32_t v = 0; v < arm.skin_model().vertex_count; ++v)
      for (int c = 0; c < 3; ++c) rest[r].push_back(arm.skin_pos(c, v));
    // Resting contact (see ReactionReturnsCriticallyDamped...): a point
    // its anchor pulls in at a = k_a d / m is caught a step late, so it
    // rests up to h^2 a + h a / (w e) inside; h differs between the rates.
    const es::SkinModel& m = arm.skin_model();
    const double mass = std::ldexp(double(m.solver.vertex_mass), -24);
    const double scale = std::ldexp(double(m.solver.stiffness_scale), -16);
    const double omega = 2 * M_PI * std::ldexp(double(m.surface.reaction_frequency), -16), h = 1.0 / hz;
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
      const double d = std::hypot(arm.skin_pos(0, v) - arm.metres(arm.skin().anchor[0][v]),
                                  arm.skin_pos(1, v) - arm.metres(arm.skin().anchor[1][v]),
                                  arm.skin_pos(2, v) - arm.metres(arm.skin().anchor[2][v]));
      const double a = std::ldexp(double(m.anchor_stiffness[v]), -16) * scale * d / mass;
      contact = std::max(contact, h * h * a + h * a / (omega * std::exp(1.0)));
    }
    std::printf("arm at %u Hz: %u reactions, largest |skin - anchor| %.2f mm\n", hz, reactions, limb_gap[r] * 1e3);
    EXPECT_GT(reactions, 0u) << "the primitives must act";
    // On the limb: within the forearm's radius (about 4 cm) of its anchor.
    EXPECT_LT(limb_gap[r], 0.04) << hz << " Hz";
  }
  double apart = 0;
  for (size_t i = 0; i < rest[0].size(); i += 3)
    apart = std::max(
        apart, std::hypot(rest[0][i] - rest[1][i], rest[0][i + 1] - rest[1][i + 1], rest[0][i + 2] - rest[1][i + 2]));
  std::printf("rest at 100 Hz vs 1 kHz: largest gap %.3f mm (resting-contact bound %.3f mm)\n", apart * 1e3,
              contact * 1e3);
  EXPECT_LT(apart, contact);
}
