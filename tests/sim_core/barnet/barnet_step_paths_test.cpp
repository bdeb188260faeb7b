// The bar-net step's shortcuts write the words of the loops they stand in
// for: the wrap's plain sums (records proven unable to saturate) against the
// saturating loop, and the three-axis solve (with and without its proof that
// every factor entry lies within +-1) against three single-axis solves.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "host_tools/layers/barnet/arm_session.hpp"
#include "sim_core/barnet/ldlt_skyline.hpp"
#include "sim_core/barnet/wide_sat.hpp"

namespace {

namespace bn = sinew::barnet;
namespace lb = sinew::layers::barnet;

std::vector<int32_t> outputs(const lb::ArmSession& s) {
  std::vector<int32_t> words;
  for (size_t c = 0; c < 3; ++c) {
    words.insert(words.end(), s.outputs().node[c].begin(), s.outputs().node[c].end());
    words.insert(words.end(), s.outputs().skin[c].begin(), s.outputs().skin[c].end());
  }
  return words;
}

void step_at(lb::ArmSession& s, double elbow_degrees) {
  s.inputs()[static_cast<size_t>(s.input("elbow.0"))] = lb::degrees_to_angle(elbow_degrees);
  ASSERT_TRUE(s.step()) << s.error();
}

// Solves v by three single-axis solves (the specification of the axes' solve).
std::vector<int64_t> solve_each_axis(const bn::SkylineFactor& f, const std::vector<int64_t>& v, uint32_t* sat) {
  std::vector<int64_t> out(v.size());
  for (size_t c = 0; c < 3; ++c) {
    std::vector<int64_t> axis(f.n);
    for (uint32_t i = 0; i < f.n; ++i) axis[i] = v[3 * i + c];
    sinew::fx::Saturation s;
    bn::ldlt_solve(f, axis, s);
    *sat += s.events;
    for (uint32_t i = 0; i < f.n; ++i) out[3 * i + c] = axis[i];
  }
  return out;
}

void expect_axes_solve_matches(const bn::SkylineFactor& f, std::mt19937_64& rng, const char* what) {
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<int64_t> v(3 * size_t{f.n});
    for (int64_t& x : v) {
      x = static_cast<int64_t>(rng() >> (3 + rng() % 61));  // |x| < 2^61, every magnitude
      if (rng() & 1) x = -x;
      if (trial % 10 == 0 && (rng() & 3) == 0) x = rng() & 1 ? bn::kVectorLimit : -bn::kVectorLimit;
    }
    uint32_t expected_sat = 0;
    const std::vector<int64_t> expected = solve_each_axis(f, v, &expected_sat);
    sinew::fx::Saturation sat;
    bn::ldlt_solve_axes(f, v, sat);
    ASSERT_EQ(v, expected) << what << ", trial " << trial;
    ASSERT_EQ(sat.events, expected_sat) << what << ", trial " << trial;
  }
}

}  // namespace

TEST(BarnetStepPaths, WrapWithoutSaturationWritesTheSaturatingLoopsWords) {
  for (const int segments : {8, 32}) {
    lb::ArmNetOptions o;
    o.segments = segments;
    lb::ArmSession s(sinew::rigc::SkinChoice::kLinear, o);
    ASSERT_TRUE(s.ok()) << s.error();
    // The builder's records are within the plain sums' bound.
    ASSERT_TRUE(s.state().wrap_bounded) << segments;
    for (const double degrees : {0.0, 45.0, 120.0, 150.0}) {
      s.state().wrap_bounded = true;
      step_at(s, degrees);
      const std::vector<int32_t> plain = outputs(s);
      const uint32_t plain_sat = s.state().stats.saturated;
      s.state().wrap_bounded = false;
      step_at(s, degrees);
      EXPECT_EQ(outputs(s), plain) << segments << " segments at " << degrees << " deg";
      EXPECT_EQ(s.state().stats.saturated, plain_sat);
    }
  }
}

TEST(BarnetStepPaths, AxesSolveIsThreeSingleAxisSolves) {
  std::mt19937_64 rng(424242);
  lb::ArmNetOptions o;
  o.segments = 32;
  lb::ArmSession s(sinew::rigc::SkinChoice::kLinear, o);
  ASSERT_TRUE(s.ok()) << s.error();
  const bn::SkylineFactor& f = s.state().factor;
  ASSERT_GT(f.lower.size(), 0u);
  expect_axes_solve_matches(f, rng, "the net's factor (entries within +-1)");

  // A factor with entries beyond +-1 takes the clamping products: the same
  // words and the same count as the single-axis solve.
  std::vector<int32_t> lower(f.lower.begin(), f.lower.end());
  lower[lower.size() / 2] = INT32_MAX;
  lower[lower.size() / 3] = INT32_MIN;
  lower[0] = sinew::fx::kUnitOne + 1;
  bn::SkylineFactor wide = f;
  wide.lower = lower;
  expect_axes_solve_matches(wide, rng, "a factor with entries beyond +-1");
}
