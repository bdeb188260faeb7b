// How far the metaballs push the skin from the bones on the built-in hand
// (metaballs-pbd-skinning, eq. 2 and 4: the skin follows balls that follow
// the bones, so it keeps its distance from them).
//
// The measure: every bone is a segment, from its joint to each child joint
// (a leaf: to the farthest skin vertex along its parent's direction), carried
// by the posed joint transforms. A finger vertex's distance to the nearest
// posed segment is compared with the bound derived from the rig:
//
//   bound = rho_rest (1 + g) + tol,
//
// rho_rest the vertex's rest distance to the nearest rest segment (the
// finger tube's radius, 8.5 mm), g the model's largest bulge gain (the
// paper's bulging is the only thing that grows a displacement: eq. 4
// carries d_ij rigidly, radius x (1 + g (1 - cos theta) / 2) <= 1 + g), and
// tol the reach of a rotation about a joint for a vertex blended between the
// two bones there: such a vertex lies in a convex blend of two rigid images
// that both keep the joint, at most sqrt(rho^2 + s^2) from it, s <= the
// rig's blend half-width (8 mm) along the bone, so at most
// sqrt(rho^2 + s^2) - rho beyond rho.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "arm_scene.hpp"

namespace {

using sinew::test::ArmScene;
namespace rigc = sinew::rigc;
namespace fx = sinew::fx;
using P3 = std::array<double, 3>;

constexpr double kFingerRadius = 0.0085;  // builtin_rigs.cpp, finger_radius
constexpr double kFingerBlend = 0.008;    // builtin_rigs.cpp, the fingers' add_tube blend

double hand_segment_distance(const P3& p, const P3& a, const P3& b) {
  P3 ab{}, ap{};
  double ab2 = 0, t = 0;
  for (size_t i = 0; i < 3; ++i) ab[i] = b[i] - a[i], ap[i] = p[i] - a[i], ab2 += ab[i] * ab[i], t += ap[i] * ab[i];
  t = ab2 > 0 ? std::clamp(t / ab2, 0.0, 1.0) : 0.0;
  double d2 = 0;
  for (size_t i = 0; i < 3; ++i) d2 += (ap[i] - t * ab[i]) * (ap[i] - t * ab[i]);
  return std::sqrt(d2);
}

struct HandSegment {
  int joint;
  P3 local_end;  // the segment's end in the joint's frame (rest rotations are identity)
};

// Segments of the hand's bones, ends in their joint's local frame.
std::vector<HandSegment> hand_segments(const rigc::RigSpec& spec) {
  const size_t nj = spec.joints.size();
  std::vector<P3> rest(nj);
  for (size_t j = 0; j < nj; ++j) {
    const int p = spec.joints[j].parent;
    for (size_t i = 0; i < 3; ++i)
      rest[j][i] = (p >= 0 ? rest[static_cast<size_t>(p)][i] : 0.0) + spec.joints[j].translation[i];
  }
  std::vector<HandSegment> segs;
  for (size_t j = 0; j < nj; ++j) {
    bool leaf = true;
    for (size_t c = 0; c < nj; ++c)
      if (spec.joints[c].parent == static_cast<int>(j)) {
        leaf = false;
        segs.push_back(
            {static_cast<int>(j), {rest[c][0] - rest[j][0], rest[c][1] - rest[j][1], rest[c][2] - rest[j][2]}});
      }
    const int p = spec.joints[j].parent;
    if (!leaf || p < 0) continue;
    P3 dir{};
    double n = 0;
    for (size_t i = 0; i < 3; ++i) dir[i] = rest[j][i] - rest[static_cast<size_t>(p)][i], n += dir[i] * dir[i];
    n = std::sqrt(n);
    double extent = 0;
    for (const auto& v : spec.vertices) {
      if (v.influences.empty() || v.influences.front().palette != static_cast<int>(j)) continue;
      double along = 0;
      for (size_t i = 0; i < 3; ++i) along += (v.position[i] - rest[j][i]) * dir[i] / n;
      extent = std::max(extent, along);
    }
    segs.push_back({static_cast<int>(j), {dir[0] / n * extent, dir[1] / n * extent, dir[2] / n * extent}});
  }
  return segs;
}

struct Ends {
  P3 a, b;
};

// Segments carried by the joints' model transforms (Mat34: Q8.24 linear
// part, Len translation); `rest` uses the rest transforms.
std::vector<Ends> posed_segments(ArmScene& s, const std::vector<HandSegment>& segs) {
  std::vector<Ends> out;
  for (const HandSegment& g : segs) {
    const fx::Mat34& m = s.engine().model[static_cast<size_t>(g.joint)];
    Ends e{};
    for (size_t i = 0; i < 3; ++i) {
      e.a[i] = s.len(m.t[i]);
      e.b[i] = e.a[i];
      for (size_t k = 0; k < 3; ++k) e.b[i] += std::ldexp(static_cast<double>(m.m[i][k]), -24) * g.local_end[k];
    }
    out.push_back(e);
  }
  return out;
}

// Distance to the nearest segment of the bones vertex v is skinned to (the
// palette of the built-in rigs is one entry per joint).
double nearest(const rigc::RigSpec& spec, uint32_t v, const P3& p, const std::vector<HandSegment>& segs,
               const std::vector<Ends>& ends) {
  double d = 1e9;
  for (size_t k = 0; k < segs.size(); ++k)
    for (const rigc::Influence& in : spec.vertices[v].influences)
      if (in.palette == segs[k].joint && in.weight > 0) d = std::min(d, hand_segment_distance(p, ends[k].a, ends[k].b));
  return d;
}

struct Reach {
  double worst_excess = -1e9;  // largest (distance - bound), m
  double farthest = 0;         // largest distance of a finger vertex, m
  uint32_t over = 0;           // vertices beyond their bound
};

// The built-in hand's finger vertices: every primitive after the palm's.
Reach measure_reach(ArmScene& s, const std::vector<HandSegment>& segs, const std::vector<double>& rest_distance,
                    double gain) {
  const std::vector<Ends> posed = posed_segments(s, segs);
  const auto& prims = s.spec().primitives;
  const double tol = std::sqrt(kFingerRadius * kFingerRadius + kFingerBlend * kFingerBlend) - kFingerRadius;
  Reach r;
  for (size_t p = 1; p < prims.size(); ++p)
    for (uint32_t v = prims[p][0]; v < prims[p][0] + prims[p][1]; ++v) {
      const double d = nearest(s.spec(), v, {s.mb(0, v), s.mb(1, v), s.mb(2, v)}, segs, posed);
      const double bound = rest_distance[v] * (1 + gain) + tol;
      r.farthest = std::max(r.farthest, d);
      r.worst_excess = std::max(r.worst_excess, d - bound);
      r.over += d > bound ? 1u : 0u;
    }
  return r;
}

TEST(MetaballsHandReach, FingerSkinStaysNearItsBones) {
  // The hand as the layer builds it by default (rig_layers.cpp: the spacing
  // 0.22 x the mean skin radius of the bones with skin).
  sinew::metaballs_build::Options o;
  o.ball_spacing = 0.22 * kFingerRadius;
  ArmScene s(rigc::builtin_hand(), o);
  ASSERT_TRUE(s.ok()) << s.error();
  double gain = 0;
  for (const auto& b : s.model().bulges) gain = std::max(gain, std::ldexp(static_cast<double>(b.gain), -30));
  const std::vector<HandSegment> segs = hand_segments(s.spec());
  ASSERT_TRUE(s.pose_dofs({}));
  std::vector<double> rest_distance(s.rig().vertex_count());
  {
    const std::vector<Ends> rest = posed_segments(s, segs);
    for (uint32_t v = 0; v < rest_distance.size(); ++v)
      rest_distance[v] = nearest(s.spec(), v, {s.rest(0, v), s.rest(1, v), s.rest(2, v)}, segs, rest);
  }
  struct Pose {
    const char* name;
    double mcp, spread, pip, wrist;
  };
  const Pose poses[] = {{"bind", 0, 0, 0, 0},
                        {"mcp 45 pip 60", 45, 0, 60, 0},
                        {"mcp 90 pip 110", 90, 0, 110, 0},
                        {"spread 20", 0, 20, 0, 0},
                        {"wrist 60 mcp 30 pip 45", 30, -15, 45, 60}};
  const char* fingers[] = {"thumb", "index", "middle", "ring", "little"};
  for (const Pose& p : poses) {
    std::vector<ArmScene::DofAngle> angles = {{"wrist", 0, p.wrist}};
    for (const char* f : fingers) {
      const std::string n = f;
      angles.push_back({n + "_mcp", 0, p.mcp});
      angles.push_back({n + "_mcp", 1, p.spread});
      angles.push_back({n + "_pip", 0, p.pip});
      angles.push_back({n + "_dip", 0, p.pip * 2 / 3});  // the rig's synergy
    }
    // Two steps: the second sees a settled PBD state.
    ASSERT_TRUE(s.pose_dofs(angles));
    ASSERT_TRUE(s.pose_dofs(angles));
    const Reach r = measure_reach(s, segs, rest_distance, gain);
    std::printf("hand %-24s farthest finger vertex %.2f mm from its bones, worst excess over bound %+.2f mm, %u over\n",
                p.name, r.farthest * 1e3, r.worst_excess * 1e3, r.over);
    EXPECT_EQ(r.over, 0u) << p.name;
  }
}

}  // namespace
