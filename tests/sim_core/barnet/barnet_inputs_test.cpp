// Bar-net inputs besides joint angles: loads activated by an external input
// (a sensor force: the value scales the force linearly between the load's
// two values) and force densities scaled by an external input at run time,
// which re-factorises D every step. Oracles: the angle-driven load of the
// same activation (the activation formula is the same, so the outputs must
// be bit-identical) and eq. (4) in double (SyntheticNet::oracle) for the
// model's q scaled as the input asks, within the final rounding and the
// solve's error (net_oracle.hpp's solve_bound).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "net_oracle.hpp"
#include "synthetic_net.hpp"

using namespace sinew::test::barnet;

namespace {

// A 7 x 7 net of spacing 1/16, border fixed, q = 1; the four nodes around the
// centre loaded along +z (set 0) and the centre row along +x (set 1).
lb::NetSpec input_test_net(int external_input, double value_hi) {
  lb::NetSpec s;
  const int n = 7;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      s.nodes.push_back(node(i / 16.0, j / 16.0, 0, i == 0 || j == 0 || i == n - 1 || j == n - 1));
  auto at = [n](int a, int b) { return static_cast<uint32_t>(a * n + b); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (i + 1 < n) s.bars.push_back({at(i, j), at(i + 1, j), 1.0});
      if (j + 1 < n) s.bars.push_back({at(i, j), at(i, j + 1), 1.0});
    }
  for (int a : {2, 3})
    for (int b : {3, 4}) {
      lb::LoadSpec l;
      l.node = at(a, b);
      l.input = 0;
      l.force = {0, 0, 1.0 / 32};
      l.external_input = external_input;
      l.value_hi = value_hi;
      s.loads.push_back(l);
    }
  for (int b = 1; b < n - 1; ++b) {
    lb::LoadSpec l;
    l.node = at(3, b);
    l.input = 1;
    l.force = {1.0 / 64, 0, 0};
    s.loads.push_back(l);
  }
  s.external_count = 2;
  return s;
}

using Positions = std::vector<std::vector<int32_t>>;

// One step with the two joint angles and the two external inputs (Q16.16).
Positions step_with_inputs(SyntheticNet& net, int32_t angle0, int32_t angle1, int32_t ext0, int32_t ext1,
                           bn::LayerStatus* status = nullptr) {
  const bn::BarnetModel& m = net.model();
  Positions out(3, std::vector<int32_t>(m.nodes.size(), 0));
  bn::StepOutputs o;
  for (size_t c = 0; c < 3; ++c) o.node[c] = out[c];
  const int32_t angles[2] = {angle0, angle1};
  const int32_t external[2] = {ext0, ext1};
  const sinew::fx::Mat34 bones[1] = {sinew::fx::mat34_identity()};
  const bn::LayerStatus s = bn::barnet_step(&net.state(), {bones, angles, external}, o);
  EXPECT_TRUE(s.ok()) << s.message;
  if (status != nullptr) *status = s;
  return out;
}

constexpr int32_t kQ16 = 1 << 16;
constexpr int32_t kRightAngle = 1 << 30;  // 90 degrees, the angle loads' full activation

}  // namespace

TEST(BarnetInputs, ExternalForceDrivesTheLoadLikeAnAngle) {
  // Set 0 driven by external input 1 (full at 10 N) in one net, by joint
  // angle 0 (full at 90 degrees) in the other: same activation, same output.
  SyntheticNet by_force(input_test_net(1, 10.0)), by_angle(input_test_net(-1, 10.0));
  ASSERT_TRUE(by_force.ok() && by_angle.ok()) << by_force.error() << by_angle.error();
  ASSERT_GE(by_force.model().loads[0].input, by_force.model().input_count) << "the load must read an external input";
  const Positions rest = step_with_inputs(by_force, 0, 0, 0, 0);
  // The angle must not move the force-driven loads, the force must.
  EXPECT_EQ(step_with_inputs(by_force, kRightAngle, 0, 0, 0), rest);
  const Positions full = step_with_inputs(by_force, 0, 0, 0, 10 * kQ16);
  EXPECT_EQ(full, step_with_inputs(by_angle, kRightAngle, 0, 0, 0));
  EXPECT_EQ(step_with_inputs(by_force, 0, 0, 0, 5 * kQ16), step_with_inputs(by_angle, kRightAngle / 2, 0, 0, 0));
  // Beyond the full value the activation clamps at 1; below 0 at 0.
  EXPECT_EQ(step_with_inputs(by_force, 0, 0, 0, 40 * kQ16), full);
  EXPECT_EQ(step_with_inputs(by_force, 0, 0, 0, -3 * kQ16), rest);

  // Against eq. (4): the full load is the oracle's set 0 (0.5 LSB of
  // rounding plus the solve's 2^-12), and the bulge is well above that.
  const auto want = by_angle.oracle(true, false);
  double worst = 0, bulge = 0, want_bulge = 0;
  for (uint32_t i = 0; i < by_force.state().free_count; ++i)
    for (size_t c = 0; c < 3; ++c) {
      worst = std::max(worst, std::abs(full[c][i] - want[c][i]));
      bulge = std::max(bulge, std::abs(static_cast<double>(full[c][i] - rest[c][i])));
      want_bulge = std::max(want_bulge, std::abs(want[c][i] - rest[c][i]));  // the rest is exact (identity bones)
    }
  // The final rounding and the solve's error (net_oracle.hpp; the loads are
  // not carried by a turning bone here, so they are exact).
  const double kBound = 0.5 + solve_bound(paper_system(by_angle.model()), want_bulge, by_angle.state().profile);
  std::printf("force-driven load: bulge %.0f LSB (eq. (4): %.2f), worst |runtime - eq. (4)| %.4f LSB\n", bulge,
              want_bulge, worst);
  EXPECT_LE(worst, kBound);
  EXPECT_LE(std::abs(bulge - want_bulge), kBound) << "the bulge is eq. (4)'s";
  EXPECT_GT(want_bulge, 2 * kBound) << "the check must tell a loaded net from a still one";

  // Half the force gives half the displacement (superposition, 1 LSB each).
  const Positions half = step_with_inputs(by_force, 0, 0, 0, 5 * kQ16);
  for (size_t c = 0; c < 3; ++c)
    for (size_t i = 0; i < rest[c].size(); ++i)
      EXPECT_LE(std::abs(2.0 * (half[c][i] - rest[c][i]) - (full[c][i] - rest[c][i])), 2.0) << c << " " << i;
}

TEST(BarnetInputs, LowerForceDensityFromAnInputGivesALargerBulge) {
  // Every bar's q follows external input 0; loads of set 0 on. Each scale is
  // checked against eq. (4) with q scaled in double (the scales are dyadic,
  // so the scaled q are exact), and the bulge grows as q falls (Fig. 3 (d)).
  lb::NetSpec spec = input_test_net(-1, 1.0);
  spec.q_inputs.push_back({0, 0, static_cast<uint32_t>(spec.bars.size())});
  SyntheticNet net(spec);
  ASSERT_TRUE(net.ok()) << net.error();
  EXPECT_GT(net.state().refactor_products, 0u);
  double previous_bulge = 0;
  for (const double scale : {4.0, 1.0, 0.5, 0.125}) {
    lb::NetSpec scaled = input_test_net(-1, 1.0);
    for (lb::BarSpec& b : scaled.bars) b.q *= scale;
    SyntheticNet reference(scaled);
    ASSERT_TRUE(reference.ok()) << reference.error();
    const auto want = reference.oracle(true, false);
    const int32_t value = static_cast<int32_t>(scale * kQ16);
    const Positions rest = step_with_inputs(net, 0, 0, value, 0);
    const Positions got = step_with_inputs(net, kRightAngle, 0, value, 0);
    double worst = 0, bulge = 0, want_bulge = 0;
    for (uint32_t i = 0; i < net.state().free_count; ++i)
      for (size_t c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(got[c][i] - want[c][i]));
        bulge = std::max(bulge, std::abs(static_cast<double>(got[c][i] - rest[c][i])));
        want_bulge = std::max(want_bulge, std::abs(want[c][i] - rest[c][i]));
      }
    std::printf("q x %.3f from the input: bulge %.0f LSB, worst |runtime - eq. (4)| %.4f LSB, saturated %u\n", scale,
                bulge, worst, net.state().stats.saturated);
    const double bound = 0.5 + solve_bound(paper_system(reference.model()), want_bulge, net.state().profile);
    EXPECT_LE(worst, bound) << "scale " << scale;
    EXPECT_EQ(net.state().stats.saturated, 0u);
    // D is linear in q: the bulge is 1 / scale times the bulge at q = 1,
    // so each lower scale must at least double it (ratios 4, 2, 4 here).
    if (previous_bulge > 0) EXPECT_GT(bulge, 2 * previous_bulge - 2) << "scale " << scale;
    previous_bulge = bulge;
  }
}

TEST(BarnetInputs, RefactorisingEveryStepKeepsNoHistory) {
  // The factor is rebuilt from the model's q and this step's inputs alone:
  // after other scales, scale 1 gives back the output of the net whose q
  // never changed, bit for bit.
  lb::NetSpec spec = input_test_net(-1, 1.0);
  SyntheticNet constant(spec);
  spec.q_inputs.push_back({1, 0, static_cast<uint32_t>(spec.bars.size() / 2)});
  SyntheticNet varying(spec);
  ASSERT_TRUE(constant.ok() && varying.ok()) << constant.error() << varying.error();
  const Positions want = step_with_inputs(constant, kRightAngle, kRightAngle, 0, 0);
  const Positions first = step_with_inputs(varying, kRightAngle, kRightAngle, 0, kQ16);
  EXPECT_EQ(first, want);
  const Positions soft = step_with_inputs(varying, kRightAngle, kRightAngle, 0, kQ16 / 3);
  EXPECT_NE(soft, want) << "scaling half the bars' q must change the loaded shape";
  step_with_inputs(varying, kRightAngle, kRightAngle, 0, 200 * kQ16);
  EXPECT_EQ(step_with_inputs(varying, kRightAngle, kRightAngle, 0, kQ16), want);
  // Positive scales beyond [2^-8, 2^8] clamp to its ends; 0 and below (what
  // an input reads before its first sample) leave the compiled q.
  EXPECT_EQ(step_with_inputs(varying, kRightAngle, kRightAngle, 0, 1),
            step_with_inputs(varying, kRightAngle, kRightAngle, 0, kQ16 >> 8));
  EXPECT_EQ(step_with_inputs(varying, kRightAngle, kRightAngle, 0, 0), want);
  EXPECT_EQ(step_with_inputs(varying, kRightAngle, kRightAngle, 0, -kQ16), want);
}

TEST(BarnetInputs, ValidationNamesTheInputRecords) {
  SyntheticNet net(input_test_net(1, 10.0));
  ASSERT_TRUE(net.ok()) << net.error();
  bn::BarnetModel m = net.model();
  m.external_count = 1;  // the loads read external input 1
  bn::LayerStatus s = bn::barnet_validate_model(m);
  EXPECT_EQ(s.error, bn::LayerError::kBadIndex);
  EXPECT_NE(std::string(s.message).find("loads[0].input"), std::string::npos) << s.message;

  m = net.model();
  std::vector<bn::ForceDensityInput> runs = {{2, 0, 1, 0}};
  m.q_inputs = runs;
  s = bn::barnet_validate_model(m);
  EXPECT_EQ(s.error, bn::LayerError::kBadIndex);
  EXPECT_NE(std::string(s.message).find("q_inputs[0].input"), std::string::npos) << s.message;
  const uint32_t last = static_cast<uint32_t>(m.bars.size()) - 1;
  const bn::ForceDensityInput empty_run[1] = {{0, 0, 0, 0}}, past_end[1] = {{0, last, 2, 0}},
                              last_bar[1] = {{0, last, 1, 0}};
  m.q_inputs = empty_run;
  EXPECT_EQ(bn::barnet_validate_model(m).error, bn::LayerError::kBadValue);
  m.q_inputs = past_end;
  EXPECT_EQ(bn::barnet_validate_model(m).error, bn::LayerError::kBadIndex);
  m.q_inputs = last_bar;
  EXPECT_TRUE(bn::barnet_validate_model(m).ok());

  // A step without the external values the model reads changes nothing.
  std::vector<int32_t> out[3];
  bn::StepOutputs o;
  for (size_t c = 0; c < 3; ++c) {
    out[c].assign(net.model().nodes.size(), 7);
    o.node[c] = out[c];
  }
  const int32_t angles[2] = {0, 0};
  const int32_t one_value[1] = {0};
  const sinew::fx::Mat34 bones[1] = {sinew::fx::mat34_identity()};
  EXPECT_EQ(bn::barnet_step(&net.state(), {bones, angles, one_value}, o).error, bn::LayerError::kBadInput);
  EXPECT_EQ(out[0][0], 7);
}
