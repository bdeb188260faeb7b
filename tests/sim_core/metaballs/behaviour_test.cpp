// Enhanced effects of metaballs-pbd-skinning: muscle bulging, secondary
// (jiggle) deformation and surface-overlap handling, on the built-in arm.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "arm_scene.hpp"

namespace {

using sinew::test::ArmScene;
namespace mbb = sinew::metaballs_build;
namespace rigc = sinew::rigc;

// ---------------------------------------------------------------- bulging

// The bulge alone (PBD and overlap off, so nothing else moves these balls
// or this skin): eq. (4) carries each ball's scale s onto the displacements
// over it, so a vertex whose balls all bulge alike sits at s times its rest
// distance from the (still) upper arm's axis.
TEST(MetaballsBulge, RadiusAndSkinGrowMonotonicallyWithFlexion) {
  constexpr double kGain = 0.3;
  mbb::Options o = sinew::test::arm_options();
  o.bulge.push_back({"shoulder", 0.3, 0.7, "shoulder", "elbow", kGain});  // a biceps over the upper arm
  ArmScene s(rigc::SkinChoice::kDualQuaternion, o);
  ASSERT_TRUE(s.ok()) << s.error();
  ASSERT_FALSE(s.model().bulges.empty());
  s.state().features.pbd = s.state().features.overlap = false;
  const uint16_t ball = s.model().bulges[s.model().bulges.size() / 2].ball;
  // Skin over the bulge: vertices of the upper arm with rest x in [0.12,
  // 0.18], each weighted only to bulging balls (checked).
  std::vector<bool> bulging(s.model().ball_count(), false);
  for (const auto& b : s.model().bulges) bulging[b.ball] = true;
  std::vector<uint32_t> skin;
  for (uint32_t v = 0; v < s.rig().vertex_count(); ++v)
    if (s.rest(0, v) >= 0.12 && s.rest(0, v) <= 0.18) {
      skin.push_back(v);
      for (uint32_t k = 0; k < sinew::metaballs::kVertexBalls; ++k) {
        const size_t i = size_t{v} * sinew::metaballs::kVertexBalls + k;
        if (s.model().vertex_weight[i] != 0) {
          ASSERT_TRUE(bulging[s.model().vertex_ball[i]]) << "vertex " << v;
        }
      }
    }
  ASSERT_FALSE(skin.empty());
  // Each skin vertex carries at most four roundings of 1/2 LSB per
  // coordinate (s d, the blended displacement, the blended centre, R D):
  // its distance from the axis is within 2 sqrt(2) LSB of s rho.
  const double skin_tol = 2 * std::sqrt(2.0) * s.len(1);
  // The scale itself: cos theta from the trace of two Q8.24 rotations (9
  // products, each entry within 1 LSB of 2^-24), over 4, times the gain, plus
  // the Q2.30 roundings of the gain and the product.
  const double scale_tol = 9 * 2 * std::ldexp(1.0, -24) / 4 * kGain + std::ldexp(1.0, -29);
  double last_radius = 0, last_skin = 0, rest_skin = 0;
  for (int deg = 0; deg <= 150; deg += 15) {
    ASSERT_TRUE(s.pose(0, deg, 0));
    const double scale = std::ldexp(s.state().ball_scale[ball], -30);
    const double radius = s.len(s.model().ball_radius[ball]) * scale;
    double mean = 0;  // distance from the upper arm's axis (the x axis: the
                      // shoulder is at rest)
    for (uint32_t v : skin) mean += std::hypot(s.mb(1, v), s.mb(2, v)) / static_cast<double>(skin.size());
    if (deg == 0) rest_skin = mean;
    std::printf(
        "bulge: elbow %3d deg, ball %u radius %.5f m, skin radius over "
        "it %.7f m (scale x rest %.7f m)\n",
        deg, ball, radius, mean, scale * rest_skin);
    if (deg > 0) {
      EXPECT_GT(radius, last_radius) << "at " << deg << " deg";
      EXPECT_GT(mean, last_skin) << "at " << deg << " deg";
      EXPECT_NEAR(mean, scale * rest_skin, skin_tol) << "at " << deg << " deg";
    }
    // r = r0 (1 + gain (1 - cos theta) / 2), theta the elbow's flexion.
    const double expected = 1 + kGain * (1 - std::cos(deg * M_PI / 180)) / 2;
    EXPECT_NEAR(scale, expected, scale_tol) << "at " << deg << " deg";
    last_radius = radius;
    last_skin = mean;
  }
}

TEST(MetaballsBulge, NoFlexionNoBulge) {
  mbb::Options o = sinew::test::arm_options();
  o.bulge.push_back({"shoulder", 0.3, 0.7, "shoulder", "elbow", 0.3});
  ArmScene s(rigc::SkinChoice::kDualQuaternion, o);
  ASSERT_TRUE(s.ok()) << s.error();
  ASSERT_TRUE(s.pose(40, 0, 0));  // the whole arm swings: no angle between the bones
  for (const auto& b : s.model().bulges) EXPECT_LE(std::abs(s.state().ball_scale[b.ball] - (1 << 30)), 64);
}

// ---------------------------------------------------------------- jiggle

struct JiggleRun {
  double moving_peak = 0;  // largest |displacement| while moving
  double first_peak = 0;   // largest |displacement| in the first 40 steps after the stop
  double lsb = 0;          // metres per Len step
  double late_peak = 0;    // largest |displacement| in steps 160-200 after the stop
  int sign_changes = 0;    // after the stop
};

// The shoulder swings 1 degree per step for 60 steps, then stops dead. The
// displacement is the mean offset of the jiggle balls from their kinematic
// centres (what the skin over them follows by eq. 4), along the swing
// direction at the stop.
JiggleRun jiggle_run(double stiffness) {
  mbb::Options o = sinew::test::arm_options();
  o.jiggle.push_back({"shoulder", 0.3, 0.7, stiffness});
  o.jiggle_damping = 0.95;
  o.jiggle_frequency = 0;  // per-step gains: stiffness and damping as given
  ArmScene s(rigc::SkinChoice::kDualQuaternion, o);
  EXPECT_TRUE(s.ok()) << s.error();
  std::vector<uint32_t> balls;
  for (uint32_t b = 0; b < s.model().ball_count(); ++b)
    if (s.model().ball_jiggle[b] > 0) balls.push_back(b);
  EXPECT_FALSE(balls.empty());
  JiggleRun run;
  run.lsb = s.len(1);
  double previous = 0;
  const double dir[2] = {-std::sin(60 * M_PI / 180), std::cos(60 * M_PI / 180)};  // swing direction at the stop
  for (int step = 0; step < 260; ++step) {
    EXPECT_TRUE(s.pose(std::min(step, 60), 0, 0));
    double d = 0;
    for (uint32_t b : balls) {
      const auto& c = s.state().ball_center[b];
      const auto& t = s.state().ball_target[b];
      d += (s.len(c.x - t.x) * dir[0] + s.len(c.y - t.y) * dir[1]) / static_cast<double>(balls.size());
    }
    const int after = step - 60;
    if (after < 0) run.moving_peak = std::max(run.moving_peak, std::fabs(d));
    if (after >= 0 && after < 40) run.first_peak = std::max(run.first_peak, std::fabs(d));
    if (after >= 160 && after < 200) run.late_peak = std::max(run.late_peak, std::fabs(d));
    if (after > 0 && (d > 0) != (previous > 0) && std::fabs(d) > 1e-6) ++run.sign_changes;
    if (std::fabs(d) > 1e-6) previous = d;
  }
  std::printf(
      "jiggle: stiffness %.2f, damping 0.95, %zu balls: lag while "
      "moving %.5f m; after the stop: first peak "
      "%.5f m, peak 160-200 steps later %.2e m, %d sign changes\n",
      stiffness, balls.size(), run.moving_peak, run.first_peak, run.late_peak, run.sign_changes);
  return run;
}

const JiggleRun& soft_run() {
  static const JiggleRun run = jiggle_run(0.05);
  return run;
}

// The decay: after the stop the target is still and a jiggle ball's swing
// e follows the spring's free recurrence e' = (1 - k)((1 + d) e - d e_prev),
// whose roots for k = 0.05, d = 0.95 are complex ((1 - k)(1 + d)^2 < 4 d)
// with modulus rho = sqrt((1 - k) d): every swing's envelope falls by rho a
// step. The stretch pairs to kinematic balls only add stiffness (they pull
// the ball towards its rest distance, (1 - k') with k' >= k), which lowers
// the modulus. The first window's peak is at most 39 steps after the stop,
// the late window starts 160 steps after it: late <= rho^121 first, plus the
// rounding of the positions (a few LSB a step, damped: 64 LSB).
TEST(MetaballsJiggle, OscillatesAndDecaysAfterASuddenStop) {
  const JiggleRun& soft = soft_run();
  EXPECT_GT(soft.first_peak, 1e-4);
  EXPECT_GE(soft.sign_changes, 3) << "the region should swing back and forth";
  const double k = 0.05, d = 0.95;
  ASSERT_LT((1 - k) * (1 + d) * (1 + d), 4 * d) << "complex roots";
  const double rho = std::sqrt((1 - k) * d);
  const double bound = std::pow(rho, 121) * soft.first_peak + 64 * soft.lsb;
  std::printf("jiggle decay: late peak %.3g m, bound rho^121 first + 64 LSB = %.3g m (rho %.4f)\n", soft.late_peak,
              bound, rho);
  EXPECT_LT(soft.late_peak, bound) << "the motion should decay";
}

TEST(MetaballsJiggle, StifferSpringGivesSmallerAmplitude) {
  const JiggleRun& soft = soft_run();
  const JiggleRun stiff = jiggle_run(0.3);
  EXPECT_LT(stiff.first_peak, soft.first_peak);
  EXPECT_LT(stiff.moving_peak, soft.moving_peak);
}

// ---------------------------------------------------------------- overlap

// Vertices of one bone's region inside a ball of the other bone's set and
// beyond the interior plane by more than 1 um (recomputed here in double).
int overlapping(ArmScene& s) {
  const auto& m = s.model();
  const auto& st = s.state();
  int count = 0;
  for (const auto& r : m.overlaps) {
    if (r.joint == sinew::metaballs::kNoJoint) continue;  // bones sharing no joint: their own test
    const auto dir = [&](uint16_t bone, sinew::fx::Vec3 d, double out[3]) {
      for (int i = 0; i < 3; ++i)
        out[i] = (st.bone[bone].m[i][0] * static_cast<double>(d.x) + st.bone[bone].m[i][1] * static_cast<double>(d.y) +
                  st.bone[bone].m[i][2] * static_cast<double>(d.z)) /
                 16777216.0 / 1073741824.0;
    };
    double da[3], db[3], n[3];
    dir(r.bone_a, r.dir_a, da);
    dir(r.bone_b, r.dir_b, db);
    for (int i = 0; i < 3; ++i) n[i] = da[i] - db[i];
    const double nn = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const auto& j = s.engine().model[r.joint];
    const auto side = [&](uint32_t v) {
      double d = 0;
      for (int i = 0; i < 3; ++i) d += (s.mb(i, v) - s.len(j.t[i])) * n[i] / nn;
      return d;
    };
    const auto inside = [&](uint32_t v, uint32_t b0, uint32_t b1) {
      for (uint32_t k = b0; k < b1; ++k) {
        const uint16_t b = m.overlap_balls[k];
        const double c[3] = {s.len(st.ball_center[b].x), s.len(st.ball_center[b].y), s.len(st.ball_center[b].z)};
        const double rad = s.len(m.ball_radius[b]) * std::ldexp(st.ball_scale[b], -30);
        const double d2 =
            std::pow(s.mb(0, v) - c[0], 2) + std::pow(s.mb(1, v) - c[1], 2) + std::pow(s.mb(2, v) - c[2], 2);
        if (d2 < rad * rad) return true;
      }
      return false;
    };
    for (uint32_t k = r.vertices_a_begin; k < r.vertices_a_end; ++k) {
      const uint32_t v = m.overlap_vertices[k];
      if (side(v) < -1e-6 && inside(v, r.balls_b_begin, r.balls_b_end)) ++count;
    }
    for (uint32_t k = r.vertices_b_begin; k < r.vertices_b_end; ++k) {
      const uint32_t v = m.overlap_vertices[k];
      if (side(v) > 1e-6 && inside(v, r.balls_a_begin, r.balls_a_end)) ++count;
    }
  }
  return count;
}

TEST(MetaballsOverlap, DeepBendLeavesNoVertexInsideTheOtherBonesBalls) {
  ArmScene with, without;
  ASSERT_TRUE(with.ok() && without.ok());
  without.state().features.overlap = false;
  for (double elbow : {90.0, 120.0, 150.0}) {
    ASSERT_TRUE(with.pose(0, elbow, 0));
    ASSERT_TRUE(without.pose(0, elbow, 0));
    const int before = overlapping(without), after = overlapping(with);
    std::printf(
        "overlap: elbow %.0f deg: vertices inside the other bone's "
        "balls beyond the interior plane: "
        "%d without handling, %d with (%u projected)\n",
        elbow, before, after, with.state().stats.projected_vertices);
    if (elbow == 150.0) {
      EXPECT_GT(before, 0) << "the deep bend should interpenetrate without handling";
    }
    EXPECT_EQ(after, 0);
  }
}

}  // namespace

// ---------------------------------------------------------------- smoothing

// Roughness of the joint region: mean | |L(v)| - |L_rest(v)| | over the
// joint-region vertices, L(v) = mean(neighbours) - v (|L| is rotation
// invariant, so a rigidly moved region scores 0).
double roughness(ArmScene& s) {
  const auto& m = s.model();
  double sum = 0;
  for (uint32_t i = 0; i < m.jv_count(); ++i) {
    const uint32_t v = m.jv_vertex[i];
    double l[3] = {0, 0, 0}, r[3] = {0, 0, 0};
    const uint32_t b = m.jv_neighbour_begin[i], e = m.jv_neighbour_begin[i + 1];
    for (uint32_t k = b; k < e; ++k)
      for (int a = 0; a < 3; ++a) {
        l[a] += (s.mb(a, m.jv_neighbours[k]) - s.mb(a, v)) / (e - b);
        r[a] += (s.rest(a, m.jv_neighbours[k]) - s.rest(a, v)) / (e - b);
      }
    sum += std::fabs(std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]) -
                     std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]));
  }
  return sum / m.jv_count();
}

// The stage is off by default (its Laplacian pulls a twisted tube inward:
// docs/metaballs.md); a rig switches it on with smoothing_passes.
TEST(MetaballsSmoothing, ShapePreservingSmoothingReducesJointRoughness) {
  mbb::Options o = sinew::test::arm_options();
  o.smoothing_passes = 2;
  ArmScene with(rigc::SkinChoice::kDualQuaternion, o), without(rigc::SkinChoice::kDualQuaternion, o);
  ASSERT_TRUE(with.ok() && without.ok());
  without.state().features.smoothing = false;
  for (double elbow : {60.0, 90.0, 120.0}) {
    ASSERT_TRUE(with.pose(0, elbow, 45));
    ASSERT_TRUE(without.pose(0, elbow, 45));
    const double r_with = roughness(with), r_without = roughness(without);
    std::printf(
        "smoothing: elbow %.0f deg, twist 45 deg: joint-region "
        "roughness %.3g m without smoothing, %.3g m with "
        "2 passes\n",
        elbow, r_without, r_with);
    EXPECT_LT(r_with, r_without);
  }
  ASSERT_TRUE(with.pose(0, 0, 0));
  EXPECT_LT(roughness(with), 1e-6) << "smoothing must leave the rest shape alone";
}
