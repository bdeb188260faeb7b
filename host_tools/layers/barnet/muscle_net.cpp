#include "muscle_net.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "host_tools/rigc/builtin_rigs.hpp"
#include "skin_tube.hpp"

namespace sinew::layers::barnet {
namespace {

constexpr double kSkinRingStep = 0.005;  // builtin_arm's ring spacing (m)

// The central lines lie on the ring's +y (biceps, the side the forearm folds
// towards: the elbow flexes about +z) and -y (triceps) nodes; ring_direction
// starts at +y, so with 8 of the skin's 32 directions they are k = 0 and 4.
constexpr int kBicepsSegment = 0;
constexpr int kTricepsSegment = kMuscleNetSegments / 2;

uint32_t tube_node(int ring, int k) {
  return static_cast<uint32_t>(ring * kMuscleNetSegments + (k % kMuscleNetSegments));
}

}  // namespace

uint32_t muscle_line_node(bool biceps, int ring) { return tube_node(ring, biceps ? kBicepsSegment : kTricepsSegment); }

bool arm_muscle_net(const rigc::RigSpec& arm, const MuscleNetOptions& o, NetSpec* out, std::string* error) {
  const int shoulder = rigc::joint_index(arm, "shoulder"), elbow = rigc::joint_index(arm, "elbow");
  const int per_ring = rigc::kArmRingSegments;
  if (shoulder < 0 || elbow < 0 || arm.vertices.size() % static_cast<size_t>(per_ring) != 0)
    return *error = "arm: not the built-in arm (joints shoulder and elbow, rings of 32 vertices)", false;
  if (!(o.q > 0) || !(o.biceps_force >= 0) || !(o.triceps_share >= 0))
    return *error = "q must be positive, biceps_force and triceps_share >= 0", false;
  const int r0 = static_cast<int>(std::floor(o.x0 / kSkinRingStep + 0.5));
  const int dr = static_cast<int>(std::floor(o.ring_step / kSkinRingStep + 0.5));
  const int last = r0 + dr * (kMuscleNetRings - 1);
  if (dr < 1 || r0 < 0 || last >= static_cast<int>(arm.vertices.size()) / per_ring)
    return *error = "x0/ring_step: outside the arm's skin", false;
  const int stride = per_ring / kMuscleNetSegments;
  NetSpec s;
  for (int c = 0; c < kMuscleNetRings; ++c)
    for (int k = 0; k < kMuscleNetSegments; ++k) {
      const rigc::VertexSpec& v = arm.vertices[static_cast<size_t>((r0 + dr * c) * per_ring + k * stride)];
      // Every node rides the upper arm alone: the net is the upper arm's
      // muscles, the fixed nodes are "on the bone".
      if (v.influences.size() != 1 || v.influences[0].palette != shoulder)
        return *error = "x0/ring_step: a ring leaves the upper arm (its skin blends in the elbow)", false;
      NodeSpec n;
      n.rest = v.position;
      const bool inner_ring = c > 0 && c < kMuscleNetRings - 1;
      n.fixed = !(inner_ring && (k == kBicepsSegment || k == kTricepsSegment));
      n.influences = v.influences;
      s.nodes.push_back(n);
    }
  add_tube_mesh(kMuscleNetRings, kMuscleNetSegments, o.q, &s);
  // Figure 3 (b): loads on the midpoints of the two central lines (the two
  // middle inner rings), radial, carried by the upper arm, activated by
  // elbow flexion.
  for (const int ring : {kMuscleNetRings / 2 - 1, kMuscleNetRings / 2})
    for (const bool biceps : {true, false}) {
      const uint32_t i = muscle_line_node(biceps, ring);
      const double ry = s.nodes[i].rest[1], rz = s.nodes[i].rest[2], r = std::sqrt(ry * ry + rz * rz);
      const double magnitude = biceps ? o.biceps_force : -o.biceps_force * o.triceps_share;
      s.loads.push_back(
          {i, shoulder, first_input_of(arm, elbow), o.flex_lo, o.flex_hi, {0, magnitude * ry / r, magnitude * rz / r}});
    }
  for (int ring = r0; ring <= last; ++ring)
    for (int k = 0; k < per_ring; ++k) s.wrap_vertices.push_back(static_cast<uint32_t>(ring * per_ring + k));
  *out = std::move(s);
  return true;
}

uint32_t joint_muscle_line_node(const JointMuscleNetOptions& o, bool flexor, int ring) {
  return static_cast<uint32_t>(ring * o.segments + (flexor ? 0 : o.segments / 2));
}

bool joint_muscle_net(const rigc::RigSpec& rig, const RigGeometry& g, int joint, const JointMuscleNetOptions& o,
                      NetSpec* out, std::string* error) {
  if (o.rings < 5 || o.rings > 15) return *error = "rings: must be 5..15", false;
  if (o.segments < 4 || o.segments > 32 || o.segments % 2 != 0) return *error = "segments: must be even, 4..32", false;
  if (!(o.span_lo >= 0 && o.span_lo < o.span_hi && o.span_hi <= 1))
    return *error = "span_lo/span_hi: must satisfy 0 <= span_lo < span_hi <= 1", false;
  if (!(o.q > 0) || !(o.force >= 0) || !(o.extensor_share >= 0))
    return *error = "q must be positive, force and extensor_share >= 0", false;
  Bend bend;
  if (!joint_bend(rig, g, joint, &bend, error)) return false;
  const std::string name = "joint '" + rig.joints[static_cast<size_t>(joint)].name + "'";
  const double radius = g.skin_radius[static_cast<size_t>(bend.parent)];
  if (!(radius > 0)) return *error = name + ": the bone before it carries no skin for the muscles", false;
  if (!(bend.length > 0)) return *error = name + ": it sits on its parent's joint: no bone for the muscles", false;
  const double force = o.force > 0 ? o.force : 0.4 * radius;
  // The tube's axis runs along the parent's bone, from its joint p0 to this one.
  const Vec3d p0 = sub(bend.c, scaled(bend.u, bend.length));
  const double t0 = o.span_lo * bend.length, t1 = o.span_hi * bend.length;
  const double step = (t1 - t0) / (o.rings - 1);
  // The parent bone's skin (its muscles' surface) near the axis.
  const std::vector<SkinSample> near =
      skin_samples(rig, g, {bend.parent}, p0, bend.u, 2.5 * radius, t0 - step, t1 + step);
  if (near.size() < 3) return *error = name + ": fewer than 3 skin vertices along the bone before it", false;

  // Node (ring, k) on the ray at angle k from the fold side, at the skin's
  // distance there, skinned as the skin vertex nearest it (the control mesh
  // is bound to the skeleton as the skin is).
  NetSpec s;
  const Vec3d a = bend.fold, b = cross(bend.u, a);
  const int flexor = 0, extensor = o.segments / 2;
  for (int ring = 0; ring < o.rings; ++ring) {
    const double t = t0 + ring * step;
    for (int k = 0; k < o.segments; ++k) {
      const TubePoint p = skin_tube_point(near, p0, bend.u, a, b, t, k, o.segments, step);
      NodeSpec n;
      n.rest = p.rest;
      // "Only the nodes lying around the central line of the two muscles
      // are set to free, all other nodes are fixed."
      n.fixed = ring == 0 || ring == o.rings - 1 || (k != flexor && k != extensor);
      n.influences = rig.vertices[p.vertex].influences;
      s.nodes.push_back(n);
    }
  }
  add_tube_mesh(o.rings, o.segments, o.q, &s);
  // Figure 3 (b): radial loads on the midpoints of the two lines (the middle
  // inner ring, or the two middle ones), carried by the parent bone and
  // activated by the joint's flexion: outwards on the flexor (it contracts
  // and bulges), inwards on the extensor (it relaxes and is stretched).
  const int inner = o.rings - 2;
  std::vector<int> loaded{(inner + 1) / 2};
  if (inner % 2 == 0) loaded = {inner / 2, inner / 2 + 1};
  for (const int ring : loaded)
    for (const bool flex : {true, false}) {
      const uint32_t i = joint_muscle_line_node(o, flex, ring);
      const Vec3d rel = sub(s.nodes[i].rest, p0);
      const Vec3d radial = normalized(sub(rel, scaled(bend.u, dot(rel, bend.u))));
      const double magnitude = flex ? force : -force * o.extensor_share;
      s.loads.push_back({i, bend.parent, bend.input, 0.0, bend.flex_hi, scaled(radial, magnitude)});
    }
  for (const SkinSample& v : near)
    if (v.axial >= t0 && v.axial <= t1) s.wrap_vertices.push_back(v.vertex);
  std::sort(s.wrap_vertices.begin(), s.wrap_vertices.end());
  if (s.wrap_vertices.empty()) return *error = name + ": no skin vertex between the muscle net's end rings", false;
  *out = std::move(s);
  return true;
}

}  // namespace sinew::layers::barnet
