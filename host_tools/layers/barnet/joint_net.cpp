#include "joint_net.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "skin_tube.hpp"
#include "volume_loads.hpp"

namespace sinew::layers::barnet {

bool joint_net(const rigc::RigSpec& rig, const RigGeometry& g, int joint, const JointNetOptions& o, NetSpec* out,
               std::string* error) {
  if (o.segments < 3 || o.segments > 32) return *error = "segments: must be 3..32", false;
  if (o.rings < 5 || o.rings > 15 || o.rings % 2 == 0) return *error = "rings: must be odd, 5..15", false;
  Bend bend;
  if (!joint_bend(rig, g, joint, &bend, error)) return false;
  const std::string name = "joint '" + rig.joints[static_cast<size_t>(joint)].name + "'";
  const int parent = bend.parent;
  const Vec3d c = bend.c, u = bend.u;
  const double radius = bend.radius;
  const double step = o.ring_step > 0 ? o.ring_step : 0.65 * radius;
  const double force = o.force > 0 ? o.force : 2.2 * radius;  // a force input's push at full value
  const Vec3d v = perpendicular(u), w = cross(u, v);
  const int mid = o.rings / 2;

  // Candidate skin: vertices of the two bones and of the joint's children
  // near the joint's axis.
  const double reach = (mid + 1) * step;
  const std::vector<SkinSample> near =
      skin_samples(rig, g, bones_around(rig, g, joint, parent), c, u, 2.5 * radius, -reach, reach);
  if (near.size() < 3) return *error = name + ": fewer than 3 skin vertices around the joint", false;

  // The control mesh is a coarse tube (the paper's control mesh need not
  // share the skin's vertices): node (ring, k) lies on the ray from the
  // axis at angle k, at the skin's distance there, so even a coarse mesh
  // gives a net. Its skin weights are those of the nearest skin vertex.
  NetSpec s;
  for (int ring = 0; ring < o.rings; ++ring) {
    const double t = (ring - mid) * step;
    for (int k = 0; k < o.segments; ++k) {
      const TubePoint p = skin_tube_point(near, c, u, v, w, t, k, o.segments, step);
      NodeSpec n;
      n.rest = p.rest;
      n.fixed = ring < 2 || ring > o.rings - 3;
      n.influences = rig.vertices[p.vertex].influences;
      s.nodes.push_back(n);
    }
  }
  auto node = [&](int ring, int k) { return static_cast<uint32_t>(ring * o.segments + (k % o.segments)); };
  add_tube_mesh(o.rings, o.segments, o.q, &s);
  // Radial loads on the middle ring, carried by the parent bone, heavier on
  // the side a positive turn folds towards (Bend::inner): scheduled over the
  // flexion to keep the control tube's volume (volume_loads.hpp), unless a
  // force or a force input asks for a linear push.
  const Vec3d inner = bend.inner;
  const double hi = bend.flex_hi;
  const bool keep_volume = o.force <= 0 && o.force_input < 0;
  RingLoadSchedule schedule;
  for (int k = 0; k < o.segments; ++k) {
    const NodeSpec& n = s.nodes[node(mid, k)];
    const Vec3d rel = sub(n.rest, c);
    const Vec3d radial = normalized(sub(rel, scaled(u, dot(rel, u))));
    const double cy = dot(radial, inner);
    const double share = o.outer_share + (1 - o.outer_share) * (1 + cy) / 2;
    if (keep_volume) {
      schedule.nodes.push_back(node(mid, k));
      schedule.push.push_back(scaled(radial, radius * share));
    } else {
      s.loads.push_back({node(mid, k), parent, bend.input, 0.0, hi, scaled(radial, force * share)});
    }
  }
  if (keep_volume) {
    schedule.rings = o.rings;
    schedule.segments = o.segments;
    schedule.carrier = parent;
    schedule.input = bend.input;
    schedule.joint = joint;
    schedule.centre = c;
    schedule.axis = bend.axis;
    schedule.flex_hi = hi;
    if (!add_volume_keeping_loads(rig, schedule, &s, error)) return *error = name + ": " + *error, false;
  }
  drive_from_inputs({o.external_count, o.force_input, o.force_input_lo, o.force_input_hi, o.q_input}, &s);
  const double lo_t = -mid * step, hi_t = mid * step;
  for (const SkinSample& cand : near)
    if (cand.axial >= lo_t && cand.axial <= hi_t) s.wrap_vertices.push_back(cand.vertex);
  std::sort(s.wrap_vertices.begin(), s.wrap_vertices.end());
  if (s.wrap_vertices.empty()) return *error = name + ": no skin vertex between the net's end rings", false;
  *out = std::move(s);
  return true;
}

}  // namespace sinew::layers::barnet
