// The world box that culls the reaction passes' inside tests
// (primitive_bound.hpp): no point it calls beyond is inside, moved or
// sampled inside by the primitive; the points that reach furthest out
// along each world axis lie within it; and it culls most of what a box
// about the primitive's surroundings holds.
#include "sim_core/muscle/primitive_bound.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sim_core/muscle/primitive.hpp"

namespace muscle = sinew::muscle;
namespace fx = sinew::fx;

// A named namespace: the test sources build as one unity file.
namespace primitive_bound_test {

constexpr double kLsb = 1.0 / (1 << 20);  // Len LSB in rig units
constexpr double kQ30 = 1073741824.0;

struct Frame {
  muscle::PrimitiveFrame f;
  double rows[3][3];  // the rotation before rounding: row i is local axis i in world
};

// A random rotation (uniform unit quaternion), its rows rounded to Q2.30 and
// each component moved by up to 2^-18, as a muscle-attached frame's are:
// near-orthonormal, not orthonormal.
Frame random_frame(std::mt19937& rng, muscle::PrimitiveKind kind, int exponent) {
  std::normal_distribution<double> n(0, 1);
  std::uniform_real_distribution<double> size(0.05, 2.0), centre(-3, 3);
  std::uniform_int_distribution<int> jitter(-(1 << 12), 1 << 12);
  double q[4];
  double len = 0;
  for (double& c : q) c = n(rng), len += c * c;
  len = std::sqrt(len);
  for (double& c : q) c /= len;
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  Frame out;
  const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)},
                          {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)},
                          {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)}};
  muscle::PrimitiveFrame& f = out.f;
  f.kind = static_cast<uint8_t>(kind);
  f.exponent = static_cast<uint8_t>(exponent);
  f.active = 1;
  f.centre = {static_cast<int32_t>(centre(rng) / kLsb), static_cast<int32_t>(centre(rng) / kLsb),
              static_cast<int32_t>(centre(rng) / kLsb)};
  for (int i = 0; i < 3; ++i) {
    for (int c = 0; c < 3; ++c) out.rows[i][c] = r[i][c];
    f.axis[i] = {static_cast<int32_t>(std::llround(r[i][0] * kQ30)) + jitter(rng),
                 static_cast<int32_t>(std::llround(r[i][1] * kQ30)) + jitter(rng),
                 static_cast<int32_t>(std::llround(r[i][2] * kQ30)) + jitter(rng)};
  }
  const double a = size(rng);
  const bool sphere = kind == muscle::PrimitiveKind::kSphere;
  f.extent[0] = static_cast<fx::Len>(a / kLsb);
  f.extent[1] = sphere ? f.extent[0] : static_cast<fx::Len>(size(rng) / kLsb);
  f.extent[2] = sphere ? f.extent[0] : static_cast<fx::Len>(size(rng) / kLsb);
  return out;
}

fx::Vec3 world_point(const Frame& fr, const double local[3]) {
  double p[3];
  for (int c = 0; c < 3; ++c) {
    p[c] = (c == 0 ? fr.f.centre.x : (c == 1 ? fr.f.centre.y : fr.f.centre.z)) * kLsb;
    for (int i = 0; i < 3; ++i) p[c] += fr.rows[i][c] * local[i];
  }
  return {static_cast<int32_t>(std::llround(p[0] / kLsb)), static_cast<int32_t>(std::llround(p[1] / kLsb)),
          static_cast<int32_t>(std::llround(p[2] / kLsb))};
}

struct Kind {
  muscle::PrimitiveKind kind;
  int exponent;
};
constexpr Kind kKinds[] = {{muscle::PrimitiveKind::kSphere, 2},
                           {muscle::PrimitiveKind::kCylinder, 2},
                           {muscle::PrimitiveKind::kSuperellipsoid, 2},
                           {muscle::PrimitiveKind::kSuperellipsoid, 4},
                           {muscle::PrimitiveKind::kSuperellipsoid, 8}};

// The primitive leaves p alone in every way a reaction pass asks.
void expect_untouched(const muscle::PrimitiveFrame& f, fx::Vec3 p) {
  ASSERT_GE(muscle::primitive_value(f, p), int64_t{1} << 30) << p.x << " " << p.y << " " << p.z;
  ASSERT_FALSE(muscle::primitive_sample(f, p).inside);
  const fx::Vec3 out = muscle::primitive_push_out(f, p, {0, 0, fx::kUnitOne}, 3);
  ASSERT_TRUE(out == p);
}

// Random points about each primitive, in a box twice its extents' reach:
// whatever the bound calls beyond, the primitive leaves alone.
TEST(PrimitiveBound, NoPointBeyondTheBoundIsInsideOrMoved) {
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> u(-1, 1);
  uint64_t beyond = 0, tested = 0;
  for (int shape = 0; shape < 200; ++shape) {
    const Kind k = kKinds[shape % 5];
    const Frame fr = random_frame(rng, k.kind, k.exponent);
    ASSERT_TRUE(muscle::near_orthonormal(fr.f.axis));
    const muscle::PrimitiveBound b = muscle::primitive_bound(fr.f);
    ASSERT_TRUE(b.usable);
    for (int i = 0; i < 400; ++i) {
      // Local points in twice the extents: a quarter of them inside the box.
      const double local[3] = {2 * u(rng) * fr.f.extent[0] * kLsb, 2 * u(rng) * fr.f.extent[1] * kLsb,
                               2 * u(rng) * fr.f.extent[2] * kLsb};
      const fx::Vec3 p = world_point(fr, local);
      ++tested;
      if (muscle::beyond_reach(b, p)) expect_untouched(fr.f, p);  // the wider reach holds it too
      if (!muscle::beyond_bound(b, p)) continue;
      ++beyond;
      expect_untouched(fr.f, p);
    }
  }
  // A cull that culls: about half of these points lie beyond the world box.
  EXPECT_GT(beyond, tested / 4);
}

// The points of each primitive that reach furthest along a world axis (on
// its surface, just inside) are not culled, and the box is no wider than
// the extents' own reach (the sum of |a_iw| e_i) by more than its slack.
TEST(PrimitiveBound, TheSurfacesFarthestPointsAreWithinTheBound) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0, 1);
  for (int shape = 0; shape < 200; ++shape) {
    const Kind k = kKinds[shape % 5];
    const Frame fr = random_frame(rng, k.kind, k.exponent);
    const muscle::PrimitiveBound b = muscle::primitive_bound(fr.f);
    const bool cylinder = k.kind == muscle::PrimitiveKind::kCylinder;
    // The box's reach per world axis, rig units: sum_i |a_iw| e_i.
    double reach[3] = {0, 0, 0}, extents = 0;
    for (int i = 0; i < 3; ++i) extents += fr.f.extent[i] * kLsb;
    for (int w = 0; w < 3; ++w)
      for (int i = 0; i < 3; ++i) reach[w] += std::fabs(fr.rows[i][w]) * fr.f.extent[i] * kLsb;
    for (int w = 0; w < 3; ++w) {
      // Wider by the slack alone: 2^-14 per extent and half an LSB each,
      // the axes' rounding and jitter (2^-18) and the rounding up.
      const double width = b.half[w] * kLsb;
      EXPECT_GE(width, reach[w]);
      EXPECT_LE(width, reach[w] + extents / 8192 + 8 * kLsb);
    }
    // Points on the surface (F = 0.998) along many directions, the
    // farthest out along each world axis kept: none of them is culled.
    double best[3] = {0, 0, 0};
    fx::Vec3 farthest[3] = {};
    for (int i = 0; i < 6000; ++i) {
      double d[3] = {n(rng), n(rng), n(rng)};
      if (cylinder) d[2] = d[2] > 0 ? 1 : -1;  // the rims reach furthest
      double norm = 0;
      for (int c = 0; c < (cylinder ? 2 : 3); ++c) norm += std::pow(std::fabs(d[c]), k.exponent);
      norm = std::pow(norm / 0.998, 1.0 / k.exponent);
      double local[3];
      for (int c = 0; c < 3; ++c) local[c] = (c == 2 && cylinder ? 0.999 * d[c] : d[c] / norm) * fr.f.extent[c] * kLsb;
      const fx::Vec3 p = world_point(fr, local);
      if (muscle::primitive_value(fr.f, p) >= int64_t{1} << 30) continue;  // rounded outside
      const int64_t offset[3] = {int64_t{p.x} - fr.f.centre.x, int64_t{p.y} - fr.f.centre.y,
                                 int64_t{p.z} - fr.f.centre.z};
      for (int w = 0; w < 3; ++w) {
        const double m = std::fabs(static_cast<double>(offset[w]));
        if (m > best[w]) best[w] = m, farthest[w] = p;
      }
      ASSERT_FALSE(muscle::beyond_bound(b, p)) << "an inside point culled";
    }
    // The surface reaches most of the way to the box (the test's points
    // probe its edge, not only its middle).
    for (int w = 0; w < 3; ++w) EXPECT_GT(best[w] * kLsb, 0.5 * reach[w]);
  }
}

// Deformed primitives, inactive ones and skewed axes get no cull.
TEST(PrimitiveBound, NotUsableWhereTheBoxDoesNotHold) {
  std::mt19937 rng(3);
  Frame fr = random_frame(rng, muscle::PrimitiveKind::kSuperellipsoid, 2);
  EXPECT_TRUE(muscle::primitive_bound(fr.f).usable);
  muscle::PrimitiveFrame bent = fr.f;
  bent.deformation.bend = muscle::kMinBend;
  EXPECT_FALSE(muscle::primitive_bound(bent).usable);
  muscle::PrimitiveFrame off = fr.f;
  off.active = 0;
  EXPECT_FALSE(muscle::primitive_bound(off).usable);
  muscle::PrimitiveFrame skewed = fr.f;
  skewed.axis[1] = skewed.axis[0];
  EXPECT_FALSE(muscle::near_orthonormal(skewed.axis));
  EXPECT_FALSE(muscle::primitive_bound(skewed).usable);
  const muscle::PrimitiveBound none = muscle::primitive_bound(off);
  EXPECT_FALSE(muscle::beyond_bound(none, {INT32_MAX, INT32_MAX, INT32_MAX}));
}

}  // namespace primitive_bound_test
