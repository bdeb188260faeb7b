// Candy wrapper and joint collapse (metaballs-pbd-skinning, "Results and
// comparisons"): the volume near the elbow and the twist joint, and the
// smallest cross-section there, for LBS, DQS and metaballs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "arm_scene.hpp"
#include "measure.hpp"

namespace {

using sinew::test::ArmScene;
namespace rigc = sinew::rigc;

struct Region {
  const char* name;
  double x0, x1;
};
constexpr Region kElbow{"elbow", 0.22, 0.38};
constexpr Region kTwist{"twist", 0.36, 0.50};

struct Figures {
  double volume;    // posed / rest
  double min_ring;  // smallest ring area, posed / rest
};

Figures measure(ArmScene& s, const Region& r, bool metaballs) {
  sinew::test::Position posed = [&](uint32_t v) {
    return metaballs ? std::array<double, 3>{s.mb(0, v), s.mb(1, v), s.mb(2, v)}
                     : std::array<double, 3>{s.skinned(0, v), s.skinned(1, v), s.skinned(2, v)};
  };
  sinew::test::Position rest = [&](uint32_t v) {
    return std::array<double, 3>{s.rest(0, v), s.rest(1, v), s.rest(2, v)};
  };
  uint32_t first = 0, last = 0;
  EXPECT_TRUE(sinew::test::ring_range(s.spec(), r.x0, r.x1, &first, &last));
  Figures f{sinew::test::tube_volume(posed, first, last) / sinew::test::tube_volume(rest, first, last), 1e9};
  for (uint32_t ring = first; ring <= last; ++ring)
    f.min_ring = std::min(f.min_ring, sinew::test::ring_area(posed, ring) / sinew::test::ring_area(rest, ring));
  return f;
}

// Under a pure twist the bones stay on the x axis, and the metaballs move
// every ring rigidly about it (one frame per ring: deform.cpp; balls on the
// axis stay there, so PBD has nothing to correct; the twist joint cannot
// fold, so nothing overlaps). The oracle: the rest rings, each turned about
// x by the angle its posed first vertex shows, closed as the measure closes
// them. The mesh's volume then differs from the rest one only by how the
// triangles between two turned rings cut the tube, and the metaballs' from
// the oracle's only by the rounding of each vertex (eps = 2.5 sqrt(3) LSB,
// cross_section_test): |dV| <= eps x surface, 2 eps / rho + 2 eps / length
// of the volume for a tube of radius >= rho closed by two caps.
void twist_volume_is_that_of_rigid_rings(ArmScene& s, const Region& r, const char* label) {
  const uint32_t n = rigc::kArmRingSegments;
  uint32_t first = 0, last = 0;
  ASSERT_TRUE(sinew::test::ring_range(s.spec(), r.x0, r.x1, &first, &last));
  std::vector<double> turn(last + 1, 0);
  double rho = 1e9;
  for (uint32_t ring = first; ring <= last; ++ring) {
    const uint32_t v = ring * n;
    turn[ring] = std::atan2(s.mb(2, v), s.mb(1, v)) - std::atan2(s.rest(2, v), s.rest(1, v));
    rho = std::min(rho, std::hypot(s.rest(1, v), s.rest(2, v)));
  }
  const sinew::test::Position oracle = [&](uint32_t v) {
    const double a = turn[v / n], y = s.rest(1, v), z = s.rest(2, v);
    return std::array<double, 3>{s.rest(0, v), std::cos(a) * y - std::sin(a) * z, std::sin(a) * y + std::cos(a) * z};
  };
  const sinew::test::Position posed = [&](uint32_t v) {
    return std::array<double, 3>{s.mb(0, v), s.mb(1, v), s.mb(2, v)};
  };
  const double v_oracle = sinew::test::tube_volume(oracle, first, last);
  const double v_mb = sinew::test::tube_volume(posed, first, last);
  const double eps = 2.5 * std::sqrt(3.0) * s.len(1);
  const double tol = 2 * eps / rho + 2 * eps / (r.x1 - r.x0);
  std::printf("%s, %s region: metaballs volume / rigid-ring oracle %.8f (bound 1 +- %.2g)\n", label, r.name,
              v_mb / v_oracle, tol);
  EXPECT_NEAR(v_mb / v_oracle, 1.0, tol) << label << " " << r.name;
}

void compare(double shoulder, double elbow, double twist, const char* label) {
  ArmScene dqs(rigc::SkinChoice::kDualQuaternion), lbs(rigc::SkinChoice::kLinear);
  ASSERT_TRUE(dqs.ok()) << dqs.error();
  ASSERT_TRUE(lbs.ok()) << lbs.error();
  ASSERT_TRUE(dqs.pose(shoulder, elbow, twist));
  ASSERT_TRUE(lbs.pose(shoulder, elbow, twist));
  for (const Region& r : {kElbow, kTwist}) {
    const Figures fl = measure(lbs, r, false), fd = measure(dqs, r, false), fm = measure(dqs, r, true);
    std::printf(
        "%s, %s region (x %.2f-%.2f m): volume/rest LBS %.4f DQS %.4f "
        "metaballs %.4f; "
        "smallest ring area/rest LBS %.4f DQS %.4f metaballs %.4f\n",
        label, r.name, r.x0, r.x1, fl.volume, fd.volume, fm.volume, fl.min_ring, fd.min_ring, fm.min_ring);
    // The paper's claim against LBS: metaballs reduce joint collapse and
    // the candy wrapper, so where LBS loses volume (beyond the rounding of
    // the measure: its vertices within a few LSB, 1e-6 of a 3.6 cm ring
    // radius) metaballs lose less. The paper gives no volume figure.
    const double rounding = 1e-6;
    // And against DQS, in the region the pose bends or twists (where LBS
    // loses volume): each DQS ring turns rigidly about a point on the arc,
    // which metaballs now match (balls of two bones and the vertices of
    // balls that turn differently are dual-quaternion blends,
    // docs/metaballs.md "Balls of two bones"), while the joint balls keep
    // the rings rigid where DQS blends them: at least DQS's volume, within
    // both skins' rounding of the measure.
    if (fl.volume < 1 - rounding) {
      EXPECT_GT(fm.volume, fl.volume) << label << " " << r.name;
      EXPECT_GE(fm.volume, fd.volume - 2 * rounding) << label << " " << r.name;
    }
    if (elbow == 0) twist_volume_is_that_of_rigid_rings(dqs, r, label);
  }
}

}  // namespace

TEST(MetaballsVolume, RestPoseReproducesTheRestMesh) {
  ArmScene s;
  ASSERT_TRUE(s.ok()) << s.error();
  ASSERT_TRUE(s.pose(0, 0, 0));
  double worst = 0;
  for (uint32_t v = 0; v < s.rig().vertex_count(); ++v)
    for (int a = 0; a < 3; ++a) worst = std::max(worst, std::fabs(s.mb(a, v) - s.rest(a, v)));
  std::printf("%s\nmetaballs: rest pose max deviation %.3g m\n", sinew::metaballs_build::summary(s.build()).c_str(),
              worst);
  EXPECT_LT(worst, 2e-6);
}

TEST(MetaballsVolume, ElbowBend30) { compare(0, 30, 0, "elbow 30 deg"); }
TEST(MetaballsVolume, ElbowBend60) { compare(0, 60, 0, "elbow 60 deg"); }
TEST(MetaballsVolume, ElbowBend90) { compare(0, 90, 0, "elbow 90 deg"); }
TEST(MetaballsVolume, ForearmTwist180) { compare(0, 0, 180, "twist 180 deg"); }
TEST(MetaballsVolume, ElbowBend90AndTwist180) { compare(0, 90, 180, "elbow 90 + twist 180 deg"); }
