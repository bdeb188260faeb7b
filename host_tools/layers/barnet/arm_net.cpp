#include "arm_net.hpp"

#include <cmath>
#include <set>
#include <utility>

#include "host_tools/layers/common/rig_geometry.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "volume_loads.hpp"

namespace sinew::layers::barnet {
namespace {

constexpr double kSkinRingStep = 0.005;  // builtin_arm's ring spacing (m)

}  // namespace

bool arm_elbow_net(const rigc::RigSpec& arm, const ArmNetOptions& o, NetSpec* out, std::string* error) {
  const int shoulder = rigc::joint_index(arm, "shoulder"), elbow = rigc::joint_index(arm, "elbow");
  const int per_ring = rigc::kArmRingSegments;
  if (shoulder < 0 || elbow < 0 || arm.vertices.size() % static_cast<size_t>(per_ring) != 0)
    return *error = "arm: not the built-in arm (joints shoulder and elbow, rings of 32 vertices)", false;
  if (o.segments <= 2 || per_ring % o.segments != 0) return *error = "segments: must divide 32 and exceed 2", false;
  if (o.rings < 2 || o.first_free_ring < 1 || o.last_free_ring >= o.rings - 1 || o.first_free_ring > o.last_free_ring)
    return *error = "rings: the free rings must lie strictly between fixed end rings", false;
  if (o.loaded_ring < o.first_free_ring || o.loaded_ring > o.last_free_ring)
    return *error = "loaded_ring: must be a free ring", false;
  const int r0 = static_cast<int>(std::floor(o.x0 / kSkinRingStep + 0.5));
  const int dr = static_cast<int>(std::floor(o.ring_step / kSkinRingStep + 0.5));
  const int skin_rings = static_cast<int>(arm.vertices.size()) / per_ring;
  if (dr < 1 || r0 < 0 || r0 + dr * (o.rings - 1) >= skin_rings)
    return *error = "x0/ring_step: outside the arm's skin", false;
  const int stride = per_ring / o.segments;
  auto skin_vertex = [&](int ring, int k) { return static_cast<uint32_t>((r0 + dr * ring) * per_ring + k * stride); };
  auto node = [&](int ring, int k) { return static_cast<uint32_t>(ring * o.segments + (k % o.segments)); };

  NetSpec s;
  for (int c = 0; c < o.rings; ++c)
    for (int k = 0; k < o.segments; ++k) {
      const rigc::VertexSpec& v = arm.vertices[skin_vertex(c, k)];
      NodeSpec n;
      n.rest = v.position;
      n.fixed = c < o.first_free_ring || c > o.last_free_ring;
      n.influences = v.influences;
      s.nodes.push_back(n);
    }
  add_tube_mesh(o.rings, o.segments, o.q, &s);
  // Radial loads on the loaded ring, heavier on the inner side (+y: the
  // elbow flexes about +z, folding the forearm towards +y), carried by the
  // upper arm and activated by elbow flexion.
  RingLoadSchedule schedule;
  for (int k = 0; k < o.segments; ++k) {
    const NodeSpec& n = s.nodes[node(o.loaded_ring, k)];
    const double ry = n.rest[1], rz = n.rest[2], r = std::sqrt(ry * ry + rz * rz);
    const double cy = ry / r, cz = rz / r;
    const double share = o.outer_share + (1 - o.outer_share) * (1 + cy) / 2;
    if (o.force > 0) {
      s.loads.push_back({node(o.loaded_ring, k),
                         shoulder,
                         first_input_of(arm, elbow),
                         o.flex_lo,
                         o.flex_hi,
                         {0, o.force * share * cy, o.force * share * cz}});
    } else {
      schedule.nodes.push_back(node(o.loaded_ring, k));
      schedule.push.push_back({0, r * share * cy, r * share * cz});
    }
  }
  if (o.force <= 0) {
    if (o.flex_lo != 0) return *error = "flexion: a volume-keeping push starts at 0 degrees", false;
    schedule.rings = o.rings;
    schedule.segments = o.segments;
    schedule.carrier = shoulder;
    schedule.input = first_input_of(arm, elbow);
    schedule.joint = elbow;
    RigGeometry g;
    if (!rig_geometry(arm, &g, error)) return false;
    schedule.centre = g.frame[static_cast<size_t>(elbow)].t;
    schedule.axis =
        dir_to_model(g.frame[static_cast<size_t>(elbow)], arm.joints[static_cast<size_t>(elbow)].dofs[0].axis);
    schedule.flex_hi = o.flex_hi;
    if (!add_volume_keeping_loads(arm, schedule, &s, error)) return false;
  }
  if (o.q_input) {
    s.external_count = 1;
    s.q_inputs.push_back({0, 0, static_cast<uint32_t>(s.bars.size())});
  }
  s.profile_order = o.profile_order;
  for (int ring = r0; ring <= r0 + dr * (o.rings - 1); ++ring)
    for (int k = 0; k < per_ring; ++k) s.wrap_vertices.push_back(static_cast<uint32_t>(ring * per_ring + k));
  *out = std::move(s);
  return true;
}

}  // namespace sinew::layers::barnet
