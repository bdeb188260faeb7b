// Completeness of the offline overlap candidates (metaballs-pbd-skinning,
// "Surface overlapping"; docs/metaballs.md, "Why the offline candidate lists
// are complete"). The runtime tests only the vertices and balls the builder
// listed near each joint. Here every joint with an overlap record is swept
// over its DOFs' full ranges (and the elbow together with the forearm
// twist); at each pose, with the projection off, every vertex of one bone's
// set is tested against every ball of the other bone's set, exactly as the
// runtime does (inside the ball, beyond the interior plane). Each such pair
// must be on the lists: a missing one is an overlap the runtime would leave.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "arm_scene.hpp"

namespace {

using sinew::test::ArmScene;
namespace rigc = sinew::rigc;

struct RangeCount {
  uint64_t overlapping = 0;  // (vertex, ball) pairs found by brute force
  uint64_t missing = 0;      // of those, not on the offline lists
  int poses = 0;
};

bool listed(const std::vector<uint32_t>& list, uint32_t v) { return std::binary_search(list.begin(), list.end(), v); }

void count_pose(ArmScene& s, RangeCount* counts) {
  const auto& m = s.model();
  const auto& st = s.state();
  const auto& vb = s.build().vertex_bone;
  ++counts->poses;
  for (const auto& r : m.overlaps) {
    if (r.joint == sinew::metaballs::kNoJoint) continue;  // bones sharing no joint: their own test
    double da[3], db[3], n[3];
    const auto dir = [&](uint16_t bone, const sinew::fx::Vec3& d, double* o) {
      const auto& t = st.bone[bone];
      const double u[3] = {std::ldexp(d.x, -30), std::ldexp(d.y, -30), std::ldexp(d.z, -30)};
      for (int i = 0; i < 3; ++i)
        o[i] = (t.m[i][0] * u[0] + t.m[i][1] * u[1] + t.m[i][2] * u[2]) / static_cast<double>(sinew::fx::kLinOne);
    };
    dir(r.bone_a, r.dir_a, da);
    dir(r.bone_b, r.dir_b, db);
    for (int i = 0; i < 3; ++i) n[i] = da[i] - db[i];
    const double nn = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(nn > 1e-9)) continue;  // bones folded onto each other: the runtime skips it too
    const auto& j = s.engine().model[r.joint];
    const auto side = [&](uint32_t v) {
      double d = 0;
      for (int i = 0; i < 3; ++i) d += (s.mb(i, v) - s.len(j.t[i])) * n[i] / nn;
      return d;
    };
    const auto inside = [&](uint32_t v, uint32_t b) {
      const double c[3] = {s.len(st.ball_center[b].x), s.len(st.ball_center[b].y), s.len(st.ball_center[b].z)};
      const double rad = s.len(m.ball_radius[b]) * std::ldexp(st.ball_scale[b], -30);
      return std::pow(s.mb(0, v) - c[0], 2) + std::pow(s.mb(1, v) - c[1], 2) + std::pow(s.mb(2, v) - c[2], 2) <
             rad * rad;
    };
    const auto span_of = [](auto whole, uint32_t b, uint32_t e) {
      const auto part = whole.subspan(b, e - b);
      std::vector<uint32_t> out(part.begin(), part.end());
      std::sort(out.begin(), out.end());
      return out;
    };
    const std::vector<uint32_t> va = span_of(m.overlap_vertices, r.vertices_a_begin, r.vertices_a_end),
                                vbl = span_of(m.overlap_vertices, r.vertices_b_begin, r.vertices_b_end),
                                ba = span_of(m.overlap_balls, r.balls_a_begin, r.balls_a_end),
                                bb = span_of(m.overlap_balls, r.balls_b_begin, r.balls_b_end);
    // sign +1: bone a's vertices must stay on the positive side, against
    // bone b's balls; -1 the other way round.
    for (int sign : {+1, -1}) {
      const uint16_t own = sign > 0 ? r.bone_a : r.bone_b, other = sign > 0 ? r.bone_b : r.bone_a;
      const std::vector<uint32_t>& verts = sign > 0 ? va : vbl;
      const std::vector<uint32_t>& balls = sign > 0 ? bb : ba;
      for (uint32_t v = 0; v < s.rig().vertex_count(); ++v) {
        if (vb[v] != own || !(sign * side(v) < -1e-7)) continue;
        for (uint32_t b = 0; b < m.ball_count(); ++b) {
          if (m.ball_bone[b] != other || !inside(v, b)) continue;
          ++counts->overlapping;
          if (!listed(verts, v) || !listed(balls, b)) ++counts->missing;
        }
      }
    }
  }
}

RangeCount sweep(ArmScene& s, const std::vector<std::vector<ArmScene::DofAngle>>& poses) {
  RangeCount c;
  s.state().features.overlap = false;
  for (const auto& p : poses) {
    EXPECT_TRUE(s.pose_dofs(p));
    count_pose(s, &c);
  }
  return c;
}

// n + 1 angles from the DOF's lower to its upper limit.
std::vector<double> range_of(const ArmScene& s, const char* joint, int dof, int n) {
  const int j = rigc::joint_index(s.spec(), joint);
  const double lo = s.dof_limit_deg(j, dof, false), hi = s.dof_limit_deg(j, dof, true);
  std::vector<double> out;
  for (int i = 0; i <= n; ++i) out.push_back(lo + (hi - lo) * i / n);
  return out;
}

RangeCount sweep_arm(const sinew::metaballs_build::Options& o);

TEST(MetaballsOverlapRange, OfflineCandidatesCoverEveryOverlapOverTheJointsRanges) {
  for (const double reach : {0.0, 2.5}) {
    sinew::metaballs_build::Options o = sinew::test::arm_options();
    o.overlap_reach = reach;  // 0: derived from the joints' ranges (the default); 2.5 radii: the former default
    const RangeCount c = sweep_arm(o);
    std::printf("overlap range, overlap_reach %.1f%s: %d poses, %llu overlapping vertex-ball pairs, %llu missing\n",
                reach, reach == 0 ? " (from the range)" : "", c.poses, static_cast<unsigned long long>(c.overlapping),
                static_cast<unsigned long long>(c.missing));
    EXPECT_GT(c.overlapping, 0u) << "the sweep never reached an overlap: it proves nothing";
    if (reach == 0) {
      EXPECT_EQ(c.missing, 0u);
    }
  }
}

RangeCount sweep_arm(const sinew::metaballs_build::Options& o) {
  ArmScene s(rigc::SkinChoice::kDualQuaternion, o);
  EXPECT_TRUE(s.ok()) << s.error();
  if (!s.ok()) return {};
  EXPECT_FALSE(s.model().overlaps.empty());
  std::printf("%s; %zu candidate vertices, %zu candidate balls\n", sinew::metaballs_build::summary(s.build()).c_str(),
              s.model().overlap_vertices.size(), s.model().overlap_balls.size());
  struct Sweep {
    const char* name;
    std::vector<std::vector<ArmScene::DofAngle>> poses;
  };
  Sweep elbow{"elbow flexion", {}}, twist{"forearm twist", {}}, wrist{"wrist (2 DOFs)", {}}, both{"elbow x twist", {}};
  for (double a : range_of(s, "elbow", 0, 60)) elbow.poses.push_back({{"elbow", 0, a}});
  for (double a : range_of(s, "forearm_twist", 0, 40)) twist.poses.push_back({{"forearm_twist", 0, a}});
  for (double a : range_of(s, "wrist", 0, 15))
    for (double b : range_of(s, "wrist", 1, 11)) wrist.poses.push_back({{"wrist", 0, a}, {"wrist", 1, b}});
  for (double a : range_of(s, "elbow", 0, 15))
    for (double b : range_of(s, "forearm_twist", 0, 8))
      both.poses.push_back({{"elbow", 0, a}, {"forearm_twist", 0, b}});
  RangeCount total;
  for (const Sweep* w : {&elbow, &twist, &wrist, &both}) {
    const RangeCount c = sweep(s, w->poses);
    std::printf("  %s, %d poses: %llu overlapping vertex-ball pairs, %llu not on the offline lists\n", w->name, c.poses,
                static_cast<unsigned long long>(c.overlapping), static_cast<unsigned long long>(c.missing));
    total.overlapping += c.overlapping;
    total.missing += c.missing;
    total.poses += c.poses;
  }
  return total;
}

}  // namespace
