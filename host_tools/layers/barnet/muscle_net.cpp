#include "muscle_net.hpp"

#include <cmath>
#include <utility>

#include "host_tools/rigc/builtin_rigs.hpp"

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

}  // namespace sinew::layers::barnet
