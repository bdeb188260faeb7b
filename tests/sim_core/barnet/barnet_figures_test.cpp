// The paper's arm figures built on the built-in arm and checked against eq.
// (4) of the appendix in double (paper_eq4.hpp):
//   - Figure 3, the biceps/triceps net: 12 free nodes on the two muscles'
//     central lines, loads on their midpoints growing with elbow flexion; the
//     biceps bulges, the triceps flattens, and halving the force densities
//     doubles the bulge (Figure 3 (d)).
//   - Figure 6, a wrinkle net on the fine mesh: the skin vertices of the
//     inner elbow are the nodes; under flexion the skin folds out of its
//     surface in creases whose depth is eq. (4)'s, and with the loads off the
//     net rests at eq. (4)'s equilibrium under its rest load.
// Both nets ride bones whose skinning keeps their rest exactly where the
// tests need it, so the runtime's displacement x - s is D^-1 p of eq. (4)
// up to: the solve before its final rounding (< 2^-12 LSB), the final
// rounding (0.5 LSB), and, for loads carried by a turning bone, the rounding
// of the carried force (<= 1 Q8.24 LSB per component, i.e. ||D^-1|| x 2^-24
// rig units).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "arm_metrics.hpp"
#include "host_tools/layers/barnet/muscle_net.hpp"
#include "host_tools/layers/barnet/wrinkle_net.hpp"
#include "net_oracle.hpp"
#include "paper_eq4.hpp"

namespace {

namespace lbf = sinew::layers::barnet;
namespace tb = sinew::test::barnet;

constexpr double kFigLenOne = 1048576.0;  // Len LSB per rig unit

lbf::ArmSession::NetBuilder muscle_builder(const lbf::MuscleNetOptions& o, bool loads = true) {
  return [o, loads](const sinew::rigc::RigSpec& arm, lbf::NetSpec* net, std::string* error) {
    if (!lbf::arm_muscle_net(arm, o, net, error)) return false;
    if (!loads) net->loads.clear();
    return true;
  };
}

lbf::ArmSession::NetBuilder wrinkle_builder(const lbf::WrinkleNetOptions& o, bool loads = true) {
  return [o, loads](const sinew::rigc::RigSpec& arm, lbf::NetSpec* net, std::string* error) {
    if (!lbf::arm_wrinkle_net(arm, o, net, error)) return false;
    if (!loads) net->loads.clear();
    return true;
  };
}

void flex_elbow(lbf::ArmSession& s, double degrees) {
  s.inputs().assign(s.inputs().size(), 0);
  s.inputs()[static_cast<size_t>(s.input("elbow.0"))] = lbf::degrees_to_angle(degrees);
  ASSERT_TRUE(s.step());
}

int32_t node_axis(const lbf::ArmSession& s, size_t c, uint32_t node) { return s.outputs().node[c][node]; }
int32_t rest_axis(const lbf::ArmSession& s, size_t c, uint32_t node) {
  const sinew::fx::Vec3 r = s.model().nodes[node].rest;
  return c == 0 ? r.x : (c == 1 ? r.y : r.z);
}

// Eq. (4)'s displacement D^-1 p (Len LSB) [c][free k] of the loads carried
// by the bones (the runtime's skinning matrices in double) at the session's
// pose, and its bound against the runtime (net_oracle.hpp).
tb::Eq4Move eq4_displacement(lbf::ArmSession& s, const tb::PaperSystem& sys) {
  return tb::eq4_move(s.model(), sys, s.state().profile, s.state().stats.max_displacement, s.engine().model,
                      s.inputs());
}

lbf::MuscleNetOptions muscle_options(double q) {
  lbf::MuscleNetOptions o;
  o.q = q;
  return o;
}

// Radial (y-z plane) displacement of node i from its rest, metres.
double radial_move(const lbf::ArmSession& s, uint32_t i) {
  const double ry = rest_axis(s, 1, i), rz = rest_axis(s, 2, i), r = std::hypot(ry, rz);
  const double dy = node_axis(s, 1, i) - ry, dz = node_axis(s, 2, i) - rz;
  return s.metres(static_cast<int32_t>(std::llround((dy * ry + dz * rz) / r)));
}

}  // namespace

TEST(BarnetFigure3, TwelveFreeNodesOnTheMusclesCentralLines) {
  lbf::ArmSession s(sinew::rigc::SkinChoice::kLinear, muscle_builder(muscle_options(1.0)));
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(s.state().free_count, static_cast<uint32_t>(lbf::kMuscleNetFreeNodes));
  EXPECT_EQ(s.model().nodes.size(), static_cast<size_t>(lbf::kMuscleNetRings * lbf::kMuscleNetSegments));
  // The free nodes are the two central lines: +y (biceps) and -y (triceps).
  for (int ring = 1; ring + 1 < lbf::kMuscleNetRings; ++ring)
    for (const bool biceps : {true, false}) {
      const uint32_t m = s.build().node_order[lbf::muscle_line_node(biceps, ring)];
      EXPECT_LT(m, s.state().free_count);
      EXPECT_EQ(rest_axis(s, 2, m), 0) << "ring " << ring;
      EXPECT_EQ(rest_axis(s, 1, m) > 0, biceps) << "ring " << ring;
    }
  // Uniform force density; every node rides the upper arm alone.
  for (const sinew::barnet::BarRecord& b : s.model().bars) EXPECT_EQ(b.q, 1 << 16);
  for (const sinew::barnet::NodeRecord& n : s.model().nodes) {
    EXPECT_EQ(n.influence_count, 1);
    EXPECT_EQ(n.joint[0], 0);
  }
  EXPECT_EQ(s.model().loads.size(), 4u);
}

TEST(BarnetFigure3, BulgeUnderFlexionIsEquation4s) {
  lbf::ArmSession s(sinew::rigc::SkinChoice::kLinear, muscle_builder(muscle_options(1.0)));
  ASSERT_TRUE(s.ok()) << s.error();
  const tb::PaperSystem sys = tb::paper_system(s.model());
  // Bind pose: the rest exactly (no activation).
  flex_elbow(s, 0);
  for (uint32_t i = 0; i < s.model().nodes.size(); ++i)
    for (size_t c = 0; c < 3; ++c) ASSERT_EQ(node_axis(s, c, i), rest_axis(s, c, i)) << "node " << i;
  // Full flexion: the upper arm has not moved, so the fixed nodes stay at
  // rest and the free ones move by D^-1 p.
  flex_elbow(s, 150);
  const tb::Eq4Move want = eq4_displacement(s, sys);
  double worst = 0;
  for (uint32_t i = s.state().free_count; i < s.model().nodes.size(); ++i)
    for (size_t c = 0; c < 3; ++c) ASSERT_EQ(node_axis(s, c, i), rest_axis(s, c, i)) << "fixed node " << i;
  for (uint32_t k = 0; k < sys.free_count; ++k)
    for (size_t c = 0; c < 3; ++c) {
      const double got = node_axis(s, c, sys.free_nodes[k]) - rest_axis(s, c, sys.free_nodes[k]);
      worst = std::max(worst, std::abs(got - want.d[c][k]));
    }
  std::printf("figure 3 net at 150 deg: largest move %.1f LSB, worst |runtime - eq. (4)| %.4f LSB (bound %.4f)\n",
              want.largest, worst, want.bound);
  EXPECT_GT(want.largest, 2 * want.bound) << "the check must tell a loaded net from a still one";
  EXPECT_LE(worst, want.bound);
}

TEST(BarnetFigure3, BicepsBulgesAndTricepsFlattensAsTheElbowFlexes) {
  lbf::ArmSession s(sinew::rigc::SkinChoice::kLinear, muscle_builder(muscle_options(1.0)));
  ASSERT_TRUE(s.ok()) << s.error();
  auto line = [&s](bool biceps, int ring) { return s.build().node_order[lbf::muscle_line_node(biceps, ring)]; };
  const int mid = lbf::kMuscleNetRings / 2;
  double last_biceps = 0, last_triceps = 0;
  for (const double degrees : {30.0, 60.0, 90.0, 120.0, 150.0}) {
    flex_elbow(s, degrees);
    const double biceps = radial_move(s, line(true, mid)), triceps = radial_move(s, line(false, mid));
    std::printf("figure 3 net at %5.1f deg: biceps midpoint +%.2f mm, triceps midpoint %.2f mm\n", degrees,
                biceps * 1e3, triceps * 1e3);
    // The loads grow linearly with flexion: the bulge grows with it.
    EXPECT_GT(biceps, last_biceps) << degrees;
    EXPECT_LT(triceps, last_triceps) << degrees;
    last_biceps = biceps, last_triceps = triceps;
    // The bulge peaks at the loaded midpoints and decays towards the fixed
    // end rings (no load between: each free node is the q-weighted mean of
    // its neighbours).
    for (const bool b : {true, false}) {
      const double sign = b ? 1 : -1;
      EXPECT_GT(sign * radial_move(s, line(b, mid - 1)), sign * radial_move(s, line(b, mid - 2))) << degrees;
      EXPECT_GT(sign * radial_move(s, line(b, mid - 2)), sign * radial_move(s, line(b, mid - 3))) << degrees;
      EXPECT_GT(sign * radial_move(s, line(b, mid - 3)), 0) << degrees;
    }
  }
  // The wrapped skin on the biceps side rises with the net: its vertex on
  // the central line at the loaded ring moves by the wrap of eq. (4)'s
  // nodes (net_oracle.hpp: the loaded against the unloaded net on the same
  // bones, each wrapped in double), within the rounding bound stated there.
  uint32_t w = 0;
  const double x_mid = s.metres(rest_axis(s, 0, line(true, mid)));
  for (uint32_t k = 0; k < s.model().wrap.size(); ++k) {
    const auto r = tb::rest(s, k);
    if (std::abs(r.x - x_mid) < 1e-9 && r.y > 0 && std::abs(r.z) < 1e-9) w = k;
  }
  const tb::NetCheck n(s.model(), s.engine().model, s.inputs(), {});
  ASSERT_TRUE(n.ok) << n.loaded.error();
  const auto exact = tb::eq4_nodes(n.unloaded, n.sys, n.move);
  std::vector<std::vector<double>> still(3, std::vector<double>(s.model().nodes.size()));
  for (size_t c = 0; c < 3; ++c)
    for (uint32_t i = 0; i < s.model().nodes.size(); ++i) still[c][i] = n.unloaded.node(c, i);
  const double want = tb::wrap_oracle(s.model(), exact, w)[1] - tb::wrap_oracle(s.model(), still, w)[1];
  const double bound = tb::wrap_bound(s.model(), n.sys.free_count, exact, n.move.bound, w) +
                       tb::wrap_bound(s.model(), n.sys.free_count, still, 0, w);
  const double rise = s.outputs().skin[1][w] - n.unloaded.skin(1, w);
  const auto net = tb::wrapped(s, w), lbs = tb::skinned(s, w);
  std::printf(
      "figure 3 skin over the biceps at 150 deg: y %.2f mm (LBS %.2f mm); rise %.1f LSB, eq. (4) %.1f "
      "(bound %.2f)\n",
      net.y * 1e3, lbs.y * 1e3, rise, want, bound);
  EXPECT_LE(std::abs(rise - want), bound);
  EXPECT_GT(want, 2 * bound) << "the check must tell a rising skin from a still one";
}

TEST(BarnetFigure3, HalvingTheForceDensityDoublesTheBulge) {
  // Figure 3 (d): "reducing the force density of the network increases the
  // size of the bulge". Eq. (4): the displacement D^-1 p with D linear in q;
  // each run's displacement is within its bound of the exact one
  // (net_oracle.hpp), so |d(q/2) - 2 d(q)| <= b(q/2) + 2 b(q).
  lbf::ArmSession stiff(sinew::rigc::SkinChoice::kLinear, muscle_builder(muscle_options(1.0)));
  lbf::ArmSession soft(sinew::rigc::SkinChoice::kLinear, muscle_builder(muscle_options(0.5)));
  ASSERT_TRUE(stiff.ok() && soft.ok()) << stiff.error() << soft.error();
  flex_elbow(stiff, 150);
  flex_elbow(soft, 150);
  double worst = 0, largest = 0;
  for (uint32_t i = 0; i < stiff.state().free_count; ++i)
    for (size_t c = 0; c < 3; ++c) {
      const double d_stiff = node_axis(stiff, c, i) - rest_axis(stiff, c, i);
      const double d_soft = node_axis(soft, c, i) - rest_axis(soft, c, i);
      worst = std::max(worst, std::abs(d_soft - 2 * d_stiff));
      largest = std::max(largest, std::abs(d_soft));
    }
  const tb::Eq4Move e_stiff = eq4_displacement(stiff, tb::paper_system(stiff.model()));
  const tb::Eq4Move e_soft = eq4_displacement(soft, tb::paper_system(soft.model()));
  const double bound = e_soft.bound + 2 * e_stiff.bound;
  std::printf("figure 3 (d): bulge %.1f LSB at q = 1/2; |d(q/2) - 2 d(q)| worst %.3f LSB (bound %.3f)\n", largest,
              worst, bound);
  EXPECT_GT(e_soft.largest, 2 * bound) << "the check must tell the bulge from none";
  EXPECT_LE(std::abs(largest - e_soft.largest), e_soft.bound);
  EXPECT_LE(worst, bound);
}

TEST(BarnetFigure6, FineMeshNetIsTheSkin) {
  lbf::ArmSession s(sinew::rigc::SkinChoice::kLinear, wrinkle_builder({}));
  ASSERT_TRUE(s.ok()) << s.error();
  // Nodes are skin vertices; every free node wraps its own vertex.
  EXPECT_EQ(s.model().wrap.size(), s.state().free_count);
  for (const double degrees : {0.0, 90.0, 150.0}) {
    flex_elbow(s, degrees);
    for (uint32_t w = 0; w < s.model().wrap.size(); ++w) {
      const sinew::barnet::WrapRecord& r = s.model().wrap[w];
      uint32_t corner = 0;
      for (uint32_t k = 1; k < 3; ++k)
        if (r.bary[k] > r.bary[corner]) corner = k;
      // The vertex and its node were rounded to Len apart: the binding's
      // weight off its corner times the triangle's size, plus the rounding.
      const sinew::barnet::ControlTriangle& t = s.model().triangles[r.triangle];
      const uint32_t node = t.node[corner];
      double off_corner = 0, span = 0;
      for (uint32_t k = 0; k < 3; ++k) {
        off_corner += std::abs(static_cast<double>(r.bary[k]) - (k == corner ? 1073741824.0 : 0.0));
        for (size_t c = 0; c < 3; ++c)
          span = std::max(span, std::abs(static_cast<double>(node_axis(s, c, t.node[k])) - node_axis(s, c, node)));
      }
      const double bound = 0.5 + off_corner / 1073741824.0 * span + std::abs(static_cast<double>(r.offset));
      ASSERT_LT(off_corner, 1 << 16) << "wrap " << w << ": not bound to its own node";
      for (size_t c = 0; c < 3; ++c)
        ASSERT_LE(std::abs(static_cast<double>(s.outputs().skin[c][w]) - node_axis(s, c, node)), bound) << degrees;
    }
  }
  // Below the activation's start the net gives back the skinned skin: the
  // bind pose is the rest exactly.
  flex_elbow(s, 0);
  for (uint32_t i = 0; i < s.model().nodes.size(); ++i)
    for (size_t c = 0; c < 3; ++c) ASSERT_EQ(node_axis(s, c, i), rest_axis(s, c, i)) << "node " << i;
}

TEST(BarnetFigure6, FlexionFoldsTheSkinIntoEquation4sCreases) {
  lbf::WrinkleNetOptions o;
  lbf::ArmSession s(sinew::rigc::SkinChoice::kLinear, wrinkle_builder(o));
  lbf::ArmSession off(sinew::rigc::SkinChoice::kLinear, wrinkle_builder(o, false));
  ASSERT_TRUE(s.ok() && off.ok()) << s.error() << off.error();
  const tb::PaperSystem sys = tb::paper_system(s.model());
  flex_elbow(s, o.flex_hi);
  flex_elbow(off, o.flex_hi);
  // Switched off (no loads), the net rests where eq. (4) puts it under its
  // rest load alone, pulled by its skinned fixed nodes (net_oracle.hpp).
  const tb::Eq4Rest rest = tb::eq4_rest(off.model(), sys, off.state().profile, off.engine().model);
  double rest_worst = 0;
  for (uint32_t k = 0; k < sys.free_count; ++k)
    for (size_t c = 0; c < 3; ++c)
      rest_worst = std::max(rest_worst, std::abs(node_axis(off, c, sys.free_nodes[k]) - rest.x[c][k]));
  std::printf("figure 6 net without loads at %.0f deg: worst |runtime - eq. (4)| %.4f LSB (bound %.4f)\n", o.flex_hi,
              rest_worst, rest.bound);
  EXPECT_LE(rest_worst, rest.bound) << "no load: the net's own equilibrium";
  // Carried forces are rounded once per component (eq4_move's bound).
  const tb::Eq4Move move = tb::eq4_move(s.model(), sys, s.state().profile,
                                        std::max(s.state().stats.max_displacement, off.state().stats.max_displacement),
                                        s.engine().model, s.inputs());
  const auto& want = move.d;
  const double bound = move.bound;
  double worst = 0;
  for (uint32_t k = 0; k < sys.free_count; ++k)
    for (size_t c = 0; c < 3; ++c) {
      const uint32_t i = sys.free_nodes[k];
      const double got = node_axis(s, c, i) - node_axis(off, c, i);
      worst = std::max(worst, std::abs(got - want[c][k]));
    }
  // The creases: along the patch's central line (the inner side, +y) the
  // skin's displacement normal to it alternates ring by ring, outwards on
  // even rings, inwards on odd ones, as deep as eq. (4) says.
  const int columns = 2 * o.half_width + 1, rings = static_cast<int>(s.model().nodes.size()) / columns;
  double shallowest = 1e30;
  for (int r = 1; r + 1 < rings; ++r) {
    const uint32_t i = s.build().node_order[static_cast<uint32_t>(r * columns + o.half_width)];
    const double ny = rest_axis(s, 1, i), nz = rest_axis(s, 2, i), n = std::hypot(ny, nz);
    // The carrying bone turns the normal: use the loaded one's direction.
    const double dy = node_axis(s, 1, i) - node_axis(off, 1, i), dz = node_axis(s, 2, i) - node_axis(off, 2, i);
    const auto k =
        static_cast<size_t>(std::find(sys.free_nodes.begin(), sys.free_nodes.end(), i) - sys.free_nodes.begin());
    const double wy = want[1][k], wz = want[2][k], wn = std::hypot(wy, wz);
    const double depth = (dy * wy + dz * wz) / wn;
    const double sign = (r % 2 == 0) ? 1 : -1;
    // The load pushes along +-n: the wanted displacement keeps its sign.
    EXPECT_GT(sign * (wy * ny + wz * nz) / n, 0) << "ring " << r;
    EXPECT_GT(depth, wn - bound) << "ring " << r;
    shallowest = std::min(shallowest, wn);
  }
  std::printf(
      "figure 6 wrinkles at %.0f deg: shallowest crease %.1f LSB (%.3f mm), worst |runtime - eq. (4)| "
      "%.4f LSB (bound %.4f)\n",
      o.flex_hi, shallowest, s.metres(static_cast<int32_t>(shallowest)) * 1e3, worst, bound);
  EXPECT_GT(shallowest, 2 * bound) << "the check must tell a crease from none";
  EXPECT_LE(worst, bound);
}

TEST(BarnetProfileOrder, SameNetWithASmallerProfile) {
  // Reverse Cuthill-McKee order of the free nodes: the same net (eq. (4) does
  // not depend on the order of its unknowns), a smaller skyline profile. Each
  // solve is within 0.5 + 2^-12 LSB of the exact positions, so the two
  // orders' outputs differ by at most 1 LSB.
  for (const int segments : {8, 32}) {
    lbf::ArmNetOptions spec_order, rcm;
    spec_order.segments = rcm.segments = segments;
    spec_order.profile_order = false;
    rcm.profile_order = true;
    lbf::ArmSession a(sinew::rigc::SkinChoice::kLinear, spec_order), b(sinew::rigc::SkinChoice::kLinear, rcm);
    ASSERT_TRUE(a.ok() && b.ok()) << a.error() << b.error();
    EXPECT_LT(b.state().profile, a.state().profile) << segments;
    int worst = 0;
    double oracle_worst = 0, bound = 0, smallest = 1e300;
    for (const double degrees : {45.0, 120.0, 150.0}) {
      flex_elbow(a, degrees);
      flex_elbow(b, degrees);
      for (uint32_t i = 0; i < a.model().nodes.size(); ++i)
        for (size_t c = 0; c < 3; ++c) {
          const uint32_t ia = a.build().node_order[i], ib = b.build().node_order[i];
          worst = std::max(worst, std::abs(node_axis(a, c, ia) - node_axis(b, c, ib)));
        }
      for (uint32_t w = 0; w < a.model().wrap.size(); ++w)
        ASSERT_EQ(a.model().wrap[w].vertex, b.model().wrap[w].vertex);
      // Both orders against eq. (4) (net_oracle.hpp), which moves the net
      // well beyond the rounding at every angle here.
      for (lbf::ArmSession* s : {&a, &b}) {
        const tb::NetCheck n(s->model(), s->engine().model, s->inputs(), {});
        ASSERT_TRUE(n.ok) << n.loaded.error();
        for (uint32_t k = 0; k < n.sys.free_count; ++k)
          for (size_t c = 0; c < 3; ++c) {
            const uint32_t i = n.sys.free_nodes[k];
            oracle_worst =
                std::max(oracle_worst, std::abs(node_axis(*s, c, i) - n.unloaded.node(c, i) - n.move.d[c][k]));
          }
        bound = std::max(bound, n.move.bound);
        smallest = std::min(smallest, n.move.largest);
      }
    }
    EXPECT_LE(oracle_worst, bound) << segments;
    EXPECT_GT(smallest, 2 * bound) << segments << ": the loads must move the net beyond the rounding";
    std::printf("%d segments: profile %u -> %u in RCM order; outputs differ by %d LSB at most\n", segments,
                a.state().profile, b.state().profile, worst);
    EXPECT_LE(worst, 1);
  }
}
