// The bar-net step's shortcuts write the words of the loops they stand in
// for: the wrap's plain sums (records proven unable to saturate) against the
// saturating loop, and the three-axis solve (with and without its proof that
// every factor entry lies within +-1, by the scalar loops and by the AVX2
// sweeps of ldlt_skyline_avx2.cpp) against three single-axis solves.
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

// The kernels this machine runs.
std::vector<bn::VectorKernel> kernels() {
  std::vector<bn::VectorKernel> k{bn::VectorKernel::kScalar};
  if (bn::vector_kernel_supported(bn::VectorKernel::kAvx2)) k.push_back(bn::VectorKernel::kAvx2);
  if (bn::vector_kernel_supported(bn::VectorKernel::kAvx512)) k.push_back(bn::VectorKernel::kAvx512);
  return k;
}

void expect_axes_solve_matches(const bn::SkylineFactor& f, std::mt19937_64& rng, const char* what) {
  for (int trial = 0; trial < 400; ++trial) {
    const bn::VectorKernel kernel = kernels()[static_cast<size_t>(trial) % kernels().size()];
    std::vector<int64_t> v(3 * size_t{f.n});
    for (int64_t& x : v) {
      x = static_cast<int64_t>(rng() >> (3 + rng() % 61));  // |x| < 2^61, every magnitude
      if (rng() & 1) x = -x;
      if (trial % 10 == 0 && (rng() & 3) == 0) x = rng() & 1 ? bn::kVectorLimit : -bn::kVectorLimit;
    }
    uint32_t expected_sat = 0;
    const std::vector<int64_t> expected = solve_each_axis(f, v, &expected_sat);
    sinew::fx::Saturation sat;
    bn::ldlt_solve_axes(f, v, sat, kernel);
    ASSERT_EQ(v, expected) << what << ", trial " << trial << ", kernel " << static_cast<int>(kernel);
    ASSERT_EQ(sat.events, expected_sat) << what << ", trial " << trial << ", kernel " << static_cast<int>(kernel);
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

// A dense factor with every entry at +-1 or near it and right-hand sides at
// the vector limit: the forward sums overflow int64 (the specification
// saturates them), the backward updates leave +-2^61 (it clamps and counts),
// in every kernel, with node counts around the lane width.
TEST(BarnetStepPaths, AxesSolveSaturatesLikeTheSpecificationInEveryKernel) {
  std::mt19937_64 rng(777);
  for (const uint32_t n : {1u, 2u, 3u, 4u, 5u, 9u, 33u}) {
    std::vector<uint32_t> first(n), offset(n + 1, 0);
    for (uint32_t i = 0; i < n; ++i) {
      first[i] = i == 0 ? 0 : static_cast<uint32_t>(rng() % (i + 1)) * (rng() % 3 == 0 ? 1u : 0u);
      offset[i + 1] = offset[i] + (i - first[i]);
    }
    std::vector<int32_t> lower(offset[n]);
    for (int32_t& l : lower) {
      const int32_t one = sinew::fx::kUnitOne;
      l = rng() % 2 ? (rng() & 1 ? one : -one)
                    : static_cast<int32_t>(static_cast<int64_t>(rng() % (2ull * one + 1)) - one);
    }
    std::vector<int64_t> recip(n);
    std::vector<int32_t> shift(n);
    for (uint32_t i = 0; i < n; ++i) {
      recip[i] = (int64_t{1} << 30) + static_cast<int64_t>(rng() % (1ull << 30));
      shift[i] = static_cast<int32_t>(rng() % 40) - 20;
    }
    bn::SkylineFactor f;
    f.n = n;
    f.first = first;
    f.offset = offset;
    f.lower = lower;
    f.recip = recip;
    f.shift = shift;
    expect_axes_solve_matches(f, rng, "a dense factor at +-1");
    // Every right-hand side at the limit, of one sign or of random signs.
    for (const bool mixed : {false, true}) {
      std::vector<int64_t> v(3 * size_t{n});
      for (int64_t& x : v) x = mixed && (rng() & 1) ? -bn::kVectorLimit : bn::kVectorLimit;
      uint32_t expected_sat = 0;
      const std::vector<int64_t> expected = solve_each_axis(f, v, &expected_sat);
      for (const bn::VectorKernel kernel : kernels()) {
        std::vector<int64_t> w = v;
        sinew::fx::Saturation sat;
        bn::ldlt_solve_axes(f, w, sat, kernel);
        EXPECT_EQ(w, expected) << n << " nodes, kernel " << static_cast<int>(kernel);
        EXPECT_EQ(sat.events, expected_sat) << n << " nodes, kernel " << static_cast<int>(kernel);
      }
    }
  }
}
