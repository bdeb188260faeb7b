#include "joint_net.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

namespace sinew::layers::barnet {
namespace {

int first_input_of(const rigc::RigSpec& rig, int joint) {
  int input = 0;
  for (int j = 0; j < joint; ++j) input += static_cast<int>(rig.joints[static_cast<size_t>(j)].dofs.size());
  return input;
}

}  // namespace

bool joint_net(const rigc::RigSpec& rig, const RigGeometry& g, int joint, const JointNetOptions& o, NetSpec* out,
               std::string* error) {
  const size_t j = static_cast<size_t>(joint);
  const rigc::JointSpec& js = rig.joints[j];
  const std::string name = "joint '" + js.name + "'";
  const int parent = anatomical_parent(rig, g, joint);
  if (parent < 0) return *error = name + " is a root: a bar-net wraps the bend between two bones", false;
  if (js.dofs.empty() || js.dof_kind != rigc::DofKind::kRotation)
    return *error = name + " has no rotational degree of freedom to drive the net's loads", false;
  if (o.segments < 3 || o.segments > 32) return *error = "segments: must be 3..32", false;
  if (o.rings < 5 || o.rings > 15 || o.rings % 2 == 0) return *error = "rings: must be odd, 5..15", false;
  const size_t p = static_cast<size_t>(parent);
  const Vec3d c = g.frame[j].t;
  Vec3d u = normalized(sub(c, g.frame[p].t));
  if (!(norm(u) > 0)) u = g.bone_dir[p];
  double radius = 0;
  int radii = 0;
  for (size_t k : {p, j})
    if (g.skin_radius[k] > 0) radius += g.skin_radius[k], ++radii;
  if (radii == 0) return *error = name + ": no skin vertex is weighted to it or its parent", false;
  radius /= radii;
  const double step = o.ring_step > 0 ? o.ring_step : 0.65 * radius;
  const double force = o.force > 0 ? o.force : 1.1 * radius;
  const Vec3d v = perpendicular(u), w = cross(u, v);
  const int mid = o.rings / 2;

  // Candidate skin: vertices of the two bones and of the joint's children
  // (a short bone's skin may belong to the next one), near the joint's axis.
  std::set<int> bones{parent, joint};
  for (size_t k = 0; k < rig.joints.size(); ++k)
    if (rig.joints[k].parent == joint || anatomical_parent(rig, g, static_cast<int>(k)) == joint)
      bones.insert(static_cast<int>(k));
  struct Candidate {
    uint32_t vertex;
    double axial;
    Vec3d radial;  // unit, perpendicular to u
    double distance;
  };
  std::vector<Candidate> near;
  for (int b : bones)
    for (uint32_t vi : g.vertices_of[static_cast<size_t>(b)]) {
      const Vec3d rel = sub(rig.vertices[vi].position, c);
      const double axial = dot(rel, u);
      const Vec3d radial = sub(rel, scaled(u, axial));
      const double d = norm(radial);
      if (d > 0 && d <= 2.5 * radius && std::fabs(axial) <= (mid + 1) * step)
        near.push_back({vi, axial, scaled(radial, 1 / d), d});
    }
  if (near.size() < 3) return *error = name + ": fewer than 3 skin vertices around the joint", false;

  // The control mesh is a coarse tube (the paper's control mesh need not
  // share the skin's vertices): node (ring, k) lies on the ray from the
  // axis at angle k, at the skin's distance there: the mean distance of the
  // skin vertices nearest that ray in angle and in height, so even a coarse
  // mesh gives a net. Its skin weights are those of the nearest of them.
  NetSpec s;
  const double pi = 3.14159265358979323846;
  for (int ring = 0; ring < o.rings; ++ring) {
    const double t = (ring - mid) * step;
    for (int k = 0; k < o.segments; ++k) {
      const double theta = 2 * pi * k / o.segments;
      const Vec3d dir = add(scaled(v, std::cos(theta)), scaled(w, std::sin(theta)));
      // Nearest candidates by a distance mixing height (in steps) and angle.
      std::vector<std::pair<double, size_t>> ranked;
      for (size_t i = 0; i < near.size(); ++i) {
        const double height = (near[i].axial - t) / step;
        const double turn = 1 - dot(near[i].radial, dir);  // 0 on the ray, 2 opposite
        ranked.push_back({height * height + 4 * turn * turn, i});
      }
      const size_t keep = std::min<size_t>(4, ranked.size());
      std::partial_sort(ranked.begin(), ranked.begin() + static_cast<std::ptrdiff_t>(keep), ranked.end());
      double rho = 0;
      for (size_t i = 0; i < keep; ++i) rho += near[ranked[i].second].distance;
      rho /= static_cast<double>(keep);
      const rigc::VertexSpec& nearest = rig.vertices[near[ranked[0].second].vertex];
      NodeSpec n;
      n.rest = add(add(c, scaled(u, t)), scaled(dir, rho));
      n.fixed = ring < 2 || ring > o.rings - 3;
      n.influences = nearest.influences;
      s.nodes.push_back(n);
    }
  }
  auto node = [&](int ring, int k) { return static_cast<uint32_t>(ring * o.segments + (k % o.segments)); };
  add_tube_mesh(o.rings, o.segments, o.q, &s);
  // Radial loads on the middle ring, carried by the parent bone, heavier on
  // the inner side of the bend: a positive turn about the DOF axis a moves
  // the distal bone towards a x u.
  const Vec3d axis = dir_to_model(g.frame[j], js.dofs[0].axis);
  const Vec3d inner = normalized(cross(axis, u));
  const double hi = js.dofs[0].max > 0 ? js.dofs[0].max : js.dofs[0].min;
  if (hi == 0) return *error = name + ": its first DOF has no range to flex through", false;
  for (int k = 0; k < o.segments; ++k) {
    const NodeSpec& n = s.nodes[node(mid, k)];
    const Vec3d rel = sub(n.rest, c);
    const Vec3d radial = normalized(sub(rel, scaled(u, dot(rel, u))));
    const double cy = dot(radial, inner);
    const double magnitude = force * (o.outer_share + (1 - o.outer_share) * (1 + cy) / 2);
    LoadSpec l{node(mid, k), parent, first_input_of(rig, joint), 0.0, hi, scaled(radial, magnitude)};
    if (o.force_input >= 0) {
      l.external_input = o.force_input;
      l.value_lo = o.force_input_lo;
      l.value_hi = o.force_input_hi;
    }
    s.loads.push_back(l);
  }
  s.external_count = o.external_count;
  if (o.q_input >= 0) s.q_inputs.push_back({o.q_input, 0, static_cast<uint32_t>(s.bars.size())});
  const double lo_t = -mid * step, hi_t = mid * step;
  for (const Candidate& cand : near)
    if (cand.axial >= lo_t && cand.axial <= hi_t) s.wrap_vertices.push_back(cand.vertex);
  std::sort(s.wrap_vertices.begin(), s.wrap_vertices.end());
  if (s.wrap_vertices.empty()) return *error = name + ": no skin vertex between the net's end rings", false;
  *out = std::move(s);
  return true;
}

}  // namespace sinew::layers::barnet
