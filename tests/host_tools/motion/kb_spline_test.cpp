// Kochanek–Bartels key postures: exact interpolation of the keys, the
// Catmull–Rom special case, tension 1 (zero tangents), continuity -1 (linear),
// C1 timing across uneven keys, and validation.
#include "host_tools/motion/kb_spline.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace sinew::motion {
namespace {

KbSpline make(const std::vector<KeyPosture>& keys) {
  KbSpline spline;
  std::string error;
  EXPECT_TRUE(KbSpline::create(keys, &spline, &error)) << error;
  return spline;
}

// Catmull–Rom on one segment, unit parameter step: the textbook matrix form.
double catmull_rom(double p0, double p1, double p2, double p3, double s) {
  return 0.5 *
         (2 * p1 + (-p0 + p2) * s + (2 * p0 - 5 * p1 + 4 * p2 - p3) * s * s + (-p0 + 3 * p1 - 3 * p2 + p3) * s * s * s);
}

double derivative(const KbSpline& spline, double time, size_t dim, double side) {
  const double h = 1e-6;
  const double a = spline.sample(time + side * h)[dim];
  const double b = spline.sample(time + side * 2 * h)[dim];
  return side * (4 * a - b - 3 * spline.sample(time)[dim]) / (2 * h);  // one-sided, second order
}

TEST(KbSpline, InterpolatesEveryKeyExactly) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::vector<KeyPosture> keys;
  double time = -0.3;
  for (int i = 0; i < 12; ++i) {
    time += 0.05 + 0.5 * (unit(rng) + 1);
    keys.push_back({time, {90 * unit(rng), 45 * unit(rng), unit(rng)}, unit(rng), unit(rng), unit(rng)});
  }
  const KbSpline spline = make(keys);
  for (const KeyPosture& key : keys) EXPECT_EQ(spline.sample(key.time), key.values);
}

TEST(KbSpline, ZeroTensionContinuityBiasIsCatmullRom) {
  const std::vector<double> p = {0, 10, 4, 25, -7, 3};
  std::vector<KeyPosture> keys;
  for (size_t i = 0; i < p.size(); ++i) keys.push_back({0.5 * static_cast<double>(i), {p[i]}, 0, 0, 0});
  const KbSpline spline = make(keys);
  // End segments use a phantom key mirrored through the end key.
  std::vector<double> q = {2 * p[0] - p[1]};
  q.insert(q.end(), p.begin(), p.end());
  q.push_back(2 * p.back() - p[p.size() - 2]);
  for (size_t seg = 0; seg + 1 < p.size(); ++seg) {
    for (double s = 0; s <= 1.0; s += 0.125) {
      const double t = 0.5 * (static_cast<double>(seg) + s);
      EXPECT_NEAR(spline.sample(t)[0], catmull_rom(q[seg], q[seg + 1], q[seg + 2], q[seg + 3], s), 1e-12)
          << "segment " << seg << " s " << s;
    }
  }
}

TEST(KbSpline, HandComputedValue) {
  // Keys 0, 1, 0 at t = 0, 1, 2. Key 1's tangent is (1 - 1)/2 = 0; key 0's
  // (mirrored phantom) is 1. At s = 1/2: h10 = 1/8, h01 = 1/2, so 1/8 + 1/2.
  const KbSpline spline = make({{0, {0}}, {1, {1}}, {2, {0}}});
  EXPECT_DOUBLE_EQ(spline.sample(0.5)[0], 0.625);
  EXPECT_DOUBLE_EQ(spline.sample(1.5)[0], 0.625);
}

TEST(KbSpline, UnevenKeysScaleTangentsToTheirSegments) {
  // Keys 0, 1, 3 at t = 0, 1, 3: at key 1 the chords are 1 and 2, averaging
  // 1.5; the outgoing tangent is scaled by 2*2/3 and the incoming by 2*1/3.
  const KbSpline spline = make({{0, {0}}, {1, {1}}, {3, {3}}});
  EXPECT_DOUBLE_EQ(spline.outgoing_tangent(1)[0], 2.0);
  EXPECT_DOUBLE_EQ(spline.incoming_tangent(1)[0], 1.0);
}

TEST(KbSpline, VelocityIsContinuousAcrossUnevenKeysWhenContinuityIsZero) {
  const KbSpline spline = make({{0, {0, 5}, 0.3, 0, -0.4},
                                {0.4, {30, -5}, -0.2, 0, 0.6},
                                {1.5, {-10, 20}, 0.5, 0, 0.1},
                                {1.7, {0, 0}, 0, 0, 0},
                                {3, {12, 1}}});
  for (double key_time : {0.4, 1.5, 1.7}) {
    for (size_t d = 0; d < 2; ++d) {
      const double left = derivative(spline, key_time, d, -1);
      const double right = derivative(spline, key_time, d, +1);
      EXPECT_NEAR(left, right, 1e-4 * (1 + std::abs(left))) << "t " << key_time << " dim " << d;
    }
  }
}

TEST(KbSpline, TensionOneGivesZeroTangents) {
  std::vector<KeyPosture> keys = {{0, {0, 1}, 1, 0.3, -0.5}, {1, {10, -2}, 1, -0.7, 0.9}, {2.5, {4, 4}, 1, 0, 0}};
  const KbSpline spline = make(keys);
  for (size_t i = 0; i < keys.size(); ++i) {
    for (double v : spline.outgoing_tangent(i)) EXPECT_EQ(v, 0.0);
    for (double v : spline.incoming_tangent(i)) EXPECT_EQ(v, 0.0);
  }
  // With zero tangents each segment is the smoothstep 3s^2 - 2s^3 between its keys.
  EXPECT_NEAR(spline.sample(0.25)[0], 10 * (3 * 0.0625 - 2 * 0.015625), 1e-12);
  EXPECT_NEAR(spline.sample(1.75)[1], -2 + 6 * 0.5, 1e-12);
  EXPECT_NEAR(derivative(spline, 1.0, 0, +1), 0.0, 1e-4);
  EXPECT_NEAR(derivative(spline, 1.0, 0, -1), 0.0, 1e-4);
}

TEST(KbSpline, ContinuityMinusOneOnEvenKeysIsLinear) {
  const KbSpline spline = make({{0, {0}, 0, -1, 0}, {1, {10}, 0, -1, 0}, {2, {4}, 0, -1, 0}, {3, {8}, 0, -1, 0}});
  EXPECT_NEAR(spline.sample(0.3)[0], 3.0, 1e-12);
  EXPECT_NEAR(spline.sample(1.25)[0], 8.5, 1e-12);
  EXPECT_NEAR(spline.sample(2.5)[0], 6.0, 1e-12);
}

TEST(KbSpline, BiasOneFollowsThroughAlongTheIncomingChord) {
  // b = 1: the outgoing tangent is the previous chord (overshoot), the
  // incoming one too; b = -1: both are the next chord.
  const KbSpline post = make({{0, {0}}, {1, {10}, 0, 0, 1}, {2, {12}}});
  EXPECT_DOUBLE_EQ(post.outgoing_tangent(1)[0], 10.0);
  EXPECT_DOUBLE_EQ(post.incoming_tangent(1)[0], 10.0);
  // Leaving key 1 along the previous chord: at s = 0.2 the Hermite basis is
  // (0.896, 0.128, 0.104, -0.032) on (10, 10, 12, 2) -> 11.424, ahead of
  // Catmull-Rom's 10.912 (outgoing tangent 6).
  EXPECT_NEAR(post.sample(1.2)[0], 11.424, 1e-12);
  EXPECT_NEAR(make({{0, {0}}, {1, {10}}, {2, {12}}}).sample(1.2)[0], 10.912, 1e-12);
  const KbSpline pre = make({{0, {0}}, {1, {10}, 0, 0, -1}, {2, {12}}});
  EXPECT_DOUBLE_EQ(pre.outgoing_tangent(1)[0], 2.0);
}

TEST(KbSpline, ClampsOutsideTheKeysAndOneKeyIsConstant) {
  const KbSpline spline = make({{1, {3, 4}}, {2, {5, 6}}});
  EXPECT_EQ(spline.sample(-10), (std::vector<double>{3, 4}));
  EXPECT_EQ(spline.sample(10), (std::vector<double>{5, 6}));
  EXPECT_EQ(spline.sample(std::nan("")), (std::vector<double>{3, 4}));
  const KbSpline one = make({{0.5, {42}}});
  EXPECT_EQ(one.sample(0)[0], 42);
  EXPECT_EQ(one.sample(7)[0], 42);
  std::vector<double> wrong_size(3);
  EXPECT_THROW(spline.sample(1.5, wrong_size), std::invalid_argument);
}

TEST(KbSpline, RejectsBadKeys) {
  struct Bad {
    const char* what;
    std::vector<KeyPosture> keys;
    const char* phrase;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Bad> cases = {
      {"no keys", {}, "no key postures"},
      {"repeated time", {{0, {1}}, {1, {2}}, {1, {3}}}, "key 2: time"},
      {"decreasing time", {{1, {1}}, {0, {2}}}, "key 1: time"},
      {"NaN time", {{0, {1}}, {nan, {2}}}, "key 1: time is not finite"},
      {"mismatched values", {{0, {1, 2}}, {1, {2}}}, "key 1: has 1 values, key 0 has 2"},
      {"infinite value", {{0, {1}}, {1, {std::numeric_limits<double>::infinity()}}}, "key 1: a value is not finite"},
      {"tension out of range", {{0, {1}, 1.5, 0, 0}}, "key 0: tension, continuity and bias"},
      {"NaN bias", {{0, {1}}, {1, {1}, 0, 0, nan}}, "key 1: tension, continuity and bias"},
  };
  for (const Bad& bad : cases) {
    KbSpline spline;
    std::string error;
    EXPECT_FALSE(KbSpline::create(bad.keys, &spline, &error)) << bad.what;
    EXPECT_NE(error.find(bad.phrase), std::string::npos) << bad.what << ": " << error;
  }
}

}  // namespace
}  // namespace sinew::motion
