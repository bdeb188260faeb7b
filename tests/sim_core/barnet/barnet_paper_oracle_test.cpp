// The fixed-point bar-net solve against a double oracle written from the
// appendix of barnet-driven-skinning (the force density method): the
// branch-node matrix C_s of eq. (1), split into its free and fixed columns
// C and C_f, D = C^t Q C and D_f = C^t Q C_f (eq. (3)), and the free nodes
// x = D^-1 (p - D_f x_f) of eq. (4). The oracle partitions the nodes by
// their kind only (no use of the runtime's node order, factor or holding
// or rest load), in double.
//
// The runtime solves x = D^-1 (p_load + p0 - D_f x_f), p0 = D_0 x0 + D_f0 x0_f
// the rest load of its bind pose (barnet_model.hpp, q_0 the compiled force
// densities). The nets below are paper nets whose free nodes rest where
// eq. (4) puts them without load, so p0 = D_0 e for e the rounding of the
// free rest positions to Len (|e| <= 0.5 LSB), and the two agree up to:
//   - D^-1 D_0 e:                                            0.5 LSB (0.5 / s
//     when a q_input scales every q by s),
//   - the solve before its final rounding (ldlt_skyline.hpp): < 2^-12 LSB,
//   - the final rounding of x to Len:                       0.5 LSB.
// Force densities, fixed positions and loads are dyadic, hence exact in
// their Q formats (checked), so the oracle's D, D_f and p are the model's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "paper_eq4.hpp"
#include "synthetic_net.hpp"

using namespace sinew::test::barnet;

namespace {

constexpr double kOracleBoundLsb = 0.5 + 0.5 + 1.0 / 4096.0;
constexpr double kLenOne = 1048576.0;  // Len LSB per rig unit

int32_t axis_of(sinew::fx::Vec3 v, size_t c) { return c == 0 ? v.x : (c == 1 ? v.y : v.z); }

// Eq. (4): free-node positions in rig units [c][free k], for the fixed
// nodes at their rest positions moved by `shift` (rig units) and the loads
// of the sets switched on.
std::vector<std::vector<double>> paper_eq4(const bn::BarnetModel& m, const PaperSystem& s, bool set0, bool set1,
                                           const double shift[3]) {
  std::vector<std::vector<double>> x(3);
  for (size_t c = 0; c < 3; ++c) {
    std::vector<double> rhs(s.free_count, 0);
    for (const bn::LoadRecord& l : m.loads) {
      if (!(l.input == 0 ? set0 : set1)) continue;
      const auto it = std::find(s.free_nodes.begin(), s.free_nodes.end(), l.node);
      rhs[static_cast<size_t>(it - s.free_nodes.begin())] += std::ldexp(axis_of(l.force, c), -24);  // p
    }
    for (uint32_t r = 0; r < s.free_count; ++r)
      for (uint32_t k = 0; k < s.fixed_count; ++k) {
        const double xf = axis_of(m.nodes[s.fixed_nodes[k]].rest, c) / kLenOne + shift[c];
        rhs[r] -= s.d_f[r * s.fixed_count + k] * xf;  // - D_f x_f
      }
    x[c] = paper_solve(s.d, rhs);
  }
  return x;
}

// Free rest positions of a spec where eq. (4) puts them with p = 0, in the
// spec's model units (the one-joint rig: model unit = 2^e rig units). The
// spec's q and fixed positions must be dyadic.
void rest_at_unloaded_equilibrium(lb::NetSpec* spec) {
  lb::NetSpec probe = *spec;
  probe.loads.clear();
  SyntheticNet net(probe);
  ASSERT_TRUE(net.ok()) << net.error();
  const PaperSystem s = paper_system(net.model());
  const double none[3] = {0, 0, 0};
  const auto x = paper_eq4(net.model(), s, false, false, none);
  for (uint32_t k = 0; k < s.free_count; ++k) {
    uint32_t spec_index = 0;
    while (net.build().node_order[spec_index] != s.free_nodes[k]) ++spec_index;
    for (size_t c = 0; c < 3; ++c) spec->nodes[spec_index].rest[c] = std::ldexp(x[c][k], net.exponent());
  }
}

struct OracleRun {
  double worst_lsb = 0;
  double largest_move = 0;  // rig units, free nodes from rest
};

// Worst |runtime - eq. (4)| in Len LSB over free nodes and axes, for the
// given load sets and a translation of the one bone (moving the fixed nodes).
// q_scale: the value of external input 0 (a model with q_inputs scales its
// bars' q by it at run time; the oracle scales Q by it).
OracleRun compare_with_eq4(SyntheticNet& net, bool set0, bool set1, const double shift[3], double q_scale = 1.0) {
  OracleRun r;
  const bn::BarnetModel& m = net.model();
  const PaperSystem s = paper_system(m, q_scale);
  const auto want = paper_eq4(m, s, set0, set1, shift);
  sinew::fx::Mat34 bone = sinew::fx::mat34_identity();
  for (size_t c = 0; c < 3; ++c) bone.t[c] = static_cast<int32_t>(std::llround(shift[c] * kLenOne));
  const int32_t on = 1 << 30;
  const int32_t angles[2] = {set0 ? on : 0, set1 ? on : 0};
  std::vector<int32_t> out[3];
  bn::StepOutputs o;
  for (size_t c = 0; c < 3; ++c) {
    out[c].assign(m.nodes.size(), 0);
    o.node[c] = out[c];
  }
  const sinew::fx::Mat34 bones[1] = {bone};
  const int32_t external[1] = {static_cast<int32_t>(std::llround(q_scale * 65536.0))};
  EXPECT_TRUE(bn::barnet_step(&net.state(), {bones, angles, external}, o).ok());
  for (uint32_t k = 0; k < s.free_count; ++k)
    for (size_t c = 0; c < 3; ++c) {
      const double got = out[c][s.free_nodes[k]];
      r.worst_lsb = std::max(r.worst_lsb, std::abs(got - want[c][k] * kLenOne));
      const double moved = (got - axis_of(m.nodes[s.free_nodes[k]].rest, c)) / kLenOne - shift[c];
      r.largest_move = std::max(r.largest_move, std::abs(moved));
    }
  return r;
}

// Force densities and loads must be exact in Q16.16 and Q8.24 for the
// oracle's D, D_f and p to be the model's (the bound above assumes it).
void expect_exact(const lb::NetSpec& spec, SyntheticNet& net) {
  for (size_t j = 0; j < spec.bars.size(); ++j)
    ASSERT_EQ(std::ldexp(static_cast<double>(net.model().bars[j].q), -16), spec.bars[j].q) << "bar " << j;
  for (size_t i = 0; i < spec.loads.size(); ++i)
    for (size_t c = 0; c < 3; ++c)
      ASSERT_EQ(std::ldexp(axis_of(net.model().loads[i].force, c), -24 + net.exponent()), spec.loads[i].force[c]);
  for (size_t i = 0; i < spec.nodes.size(); ++i)
    if (spec.nodes[i].fixed)
      for (size_t c = 0; c < 3; ++c)
        ASSERT_EQ(std::ldexp(axis_of(net.model().nodes[net.build().node_order[i]].rest, c), net.exponent() - 20),
                  spec.nodes[i].rest[c]);
}

// A square net of side n nodes, spacing 1/16, border fixed, uniform q: the
// hanging net of form finding, each free node loaded by its weight
// (set 0, -z) and the four nodes around the centre pushed up (set 1, +z).
lb::NetSpec hanging_net(int n, double q, double weight) {
  lb::NetSpec s;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const bool fixed = i == 0 || j == 0 || i == n - 1 || j == n - 1;
      s.nodes.push_back(node(i / 16.0, j / 16.0, 0, fixed));
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const auto at = [n](int a, int b) { return static_cast<uint32_t>(a * n + b); };
      if (i + 1 < n) s.bars.push_back({at(i, j), at(i + 1, j), q});
      if (j + 1 < n) s.bars.push_back({at(i, j), at(i, j + 1), q});
    }
  for (uint32_t k = 0; k < s.nodes.size(); ++k) {
    if (s.nodes[k].fixed) continue;
    lb::LoadSpec l;
    l.node = k;
    l.input = 0;
    l.force = {0, 0, -weight};
    s.loads.push_back(l);
  }
  const int c = n / 2;
  for (int a : {c - 1, c})
    for (int b : {c - 1, c}) {
      lb::LoadSpec l;
      l.node = static_cast<uint32_t>(a * n + b);
      l.input = 1;
      l.force = {weight, 0, 4 * weight};
      s.loads.push_back(l);
    }
  return s;
}

// The arm of figure 3 in miniature: a tube of 6 rings of 8 nodes, the end
// rings fixed, loads pushing the middle rings' nodes outward (the muscle
// bulge of figure 3 (b)-(c)); force densities vary along the tube, so the
// free rest positions (the unloaded equilibrium) are not dyadic.
lb::NetSpec muscle_tube(double q_scale) {
  lb::NetSpec s;
  const int rings = 6, around = 8;
  const double ring_x[around] = {1, 0.75, 0, -0.75, -1, -0.75, 0, 0.75};
  const double ring_y[around] = {0, 0.75, 1, 0.75, 0, -0.75, -1, -0.75};
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < around; ++k)
      s.nodes.push_back(node(ring_x[k] / 8, ring_y[k] / 8, r / 8.0, r == 0 || r == rings - 1));
  const double along_q[rings] = {1, 0.75, 1.5, 0.5, 1.25, 1};
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < around; ++k) {
      const uint32_t i = static_cast<uint32_t>(r * around + k);
      s.bars.push_back({i, static_cast<uint32_t>(r * around + (k + 1) % around), 2 * q_scale});
      if (r + 1 < rings) s.bars.push_back({i, i + around, along_q[r] * q_scale});
    }
  for (int r = 2; r <= 3; ++r)
    for (int k = 0; k < around; ++k) {
      lb::LoadSpec l;
      l.node = static_cast<uint32_t>(r * around + k);
      l.input = r == 2 ? 0 : 1;
      l.force = {ring_x[k] / 64, ring_y[k] / 64, r == 2 ? -1.0 / 128 : 1.0 / 128};
      s.loads.push_back(l);
    }
  return s;
}

}  // namespace

TEST(BarnetPaperOracle, HangingNetMatchesEquation4) {
  lb::NetSpec spec = hanging_net(9, 1.0, 1.0 / 64);
  SyntheticNet net(spec);
  ASSERT_TRUE(net.ok()) << net.error();
  expect_exact(spec, net);
  const double none[3] = {0, 0, 0};
  double worst = 0, sag = 0;
  for (int combo = 0; combo < 4; ++combo) {
    const OracleRun r = compare_with_eq4(net, combo & 1, combo & 2, none);
    worst = std::max(worst, r.worst_lsb);
    if (combo == 1) sag = r.largest_move;
  }
  std::printf("hanging net 9x9: sag %.4f rig units, worst |runtime - eq. (4)| %.4f LSB (bound %.4f)\n", sag, worst,
              kOracleBoundLsb);
  EXPECT_GT(sag, kOracleBoundLsb / kLenOne) << "the weights must make the net sag beyond the solve's error";
  EXPECT_LE(worst, kOracleBoundLsb);
}

TEST(BarnetPaperOracle, MuscleTubeMatchesEquation4) {
  lb::NetSpec spec = muscle_tube(1.0);
  rest_at_unloaded_equilibrium(&spec);
  SyntheticNet net(spec);
  ASSERT_TRUE(net.ok()) << net.error();
  expect_exact(spec, net);
  const double none[3] = {0, 0, 0};
  double worst = 0;
  for (int combo = 0; combo < 4; ++combo)
    worst = std::max(worst, compare_with_eq4(net, combo & 1, combo & 2, none).worst_lsb);
  std::printf("muscle tube: worst |runtime - eq. (4)| %.4f LSB (bound %.4f)\n", worst, kOracleBoundLsb);
  EXPECT_LE(worst, kOracleBoundLsb);
}

TEST(BarnetPaperOracle, TranslatedFixedNodesCarryTheNet) {
  // Moving the fixed nodes (x_f) moves the free ones through - D_f x_f:
  // the bone's translation carries the fixed nodes, and eq. (4) with the
  // moved x_f must match (the rows of [D D_f] sum to 0, so it is the same
  // translation of the loaded shape). The fixed nodes pulling the free ones
  // when they move apart non-rigidly is BarnetArm.NetTakesItsFormFromTheFixedNodes.
  lb::NetSpec spec = muscle_tube(1.0);
  rest_at_unloaded_equilibrium(&spec);
  SyntheticNet net(spec);
  ASSERT_TRUE(net.ok()) << net.error();
  const double shift[3] = {0.25, -0.125, 0.375};
  const OracleRun r = compare_with_eq4(net, true, true, shift);
  std::printf("muscle tube, fixed nodes moved: worst %.4f LSB\n", r.worst_lsb);
  EXPECT_LE(r.worst_lsb, kOracleBoundLsb);
}

TEST(BarnetPaperOracle, HalvingTheForceDensitiesDoublesTheBulge) {
  // Figure 3 (d): "reducing the force density of the network increases the
  // size of the bulge". D = C^t Q C is linear in q, so under the same loads
  // halving every q doubles each free node's displacement, exactly in eq.
  // (4); the runtime's two displacements each carry the oracle bound.
  lb::NetSpec stiff = muscle_tube(1.0), soft = muscle_tube(0.5);
  rest_at_unloaded_equilibrium(&stiff);
  rest_at_unloaded_equilibrium(&soft);
  SyntheticNet a(stiff), b(soft);
  ASSERT_TRUE(a.ok() && b.ok()) << a.error() << b.error();
  const auto rest = a.step(false, false);
  const auto bulge_stiff = a.step(true, true);
  const auto rest_soft = b.step(false, false);
  const auto bulge_soft = b.step(true, true);
  double worst = 0, largest = 0;
  for (size_t c = 0; c < 3; ++c)
    for (size_t i = 0; i < rest[c].size(); ++i) {
      const double d_stiff = bulge_stiff[c][i] - rest[c][i], d_soft = bulge_soft[c][i] - rest_soft[c][i];
      largest = std::max(largest, std::abs(d_soft));
      // Each displacement is the difference of two solves with a common
      // rest: 2 x the oracle bound each, the stiff one doubled.
      worst = std::max(worst, std::abs(d_soft - 2 * d_stiff));
    }
  std::printf("muscle tube: bulge %.1f LSB at q/2; |d(q/2) - 2 d(q)| worst %.3f LSB (bound %.3f)\n", largest, worst,
              6 * kOracleBoundLsb);
  EXPECT_GT(largest, 6 * kOracleBoundLsb) << "the loads must bulge the tube beyond the solve's error";
  EXPECT_LE(worst, 6 * kOracleBoundLsb);
}

TEST(BarnetPaperOracle, ForceDensityFromAnInputFollowsEquation4) {
  // Figure 3 (d) at run time: one net whose bars' q all follow external
  // input 0, re-factorised each step. Eq. (4) with Q scaled in double is the
  // oracle at every scale (dyadic scales of dyadic q: exact in Q16.16; a
  // uniform scale keeps the unloaded equilibrium, so the rest stays where
  // eq. (4) puts it). The paper's finding, lower q a larger bulge, follows
  // with the factor 1 / scale of eq. (4)'s linearity in Q.
  lb::NetSpec spec = muscle_tube(1.0);
  rest_at_unloaded_equilibrium(&spec);
  spec.external_count = 1;
  spec.q_inputs.push_back({0, 0, static_cast<uint32_t>(spec.bars.size())});
  SyntheticNet net(spec);
  ASSERT_TRUE(net.ok()) << net.error();
  const double none[3] = {0, 0, 0};
  double bulge_at_one = 0;
  for (const double scale : {1.0, 0.5, 0.25, 2.0}) {
    double worst = 0;
    for (int combo = 0; combo < 4; ++combo)
      worst = std::max(worst, compare_with_eq4(net, combo & 1, combo & 2, none, scale).worst_lsb);
    const double bulge = compare_with_eq4(net, true, true, none, scale).largest_move * kLenOne;
    if (scale == 1.0) bulge_at_one = bulge;
    std::printf("muscle tube, q x %.2f from the input: bulge %.1f LSB, worst |runtime - eq. (4)| %.4f LSB\n", scale,
                bulge, worst);
    const double bound = 0.5 / scale + 0.5 + 1.0 / 4096.0;  // header comment
    EXPECT_LE(worst, bound) << "scale " << scale;
    // Eq. (4): the displacement is D^-1 p, D linear in Q, so the bulge is
    // bulge(1) / scale up to the oracle bound on each of the two runs.
    EXPECT_NEAR(bulge, bulge_at_one / scale, 2 * kOracleBoundLsb / scale + 2 * bound) << "scale " << scale;
  }
  EXPECT_GT(bulge_at_one, 6 * kOracleBoundLsb) << "the loads must bulge the tube beyond the solve's error";
}
