#include "skin_tube.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace sinew::layers::barnet {

bool joint_bend(const rigc::RigSpec& rig, const RigGeometry& g, int joint, Bend* out, std::string* error) {
  const size_t j = static_cast<size_t>(joint);
  const rigc::JointSpec& js = rig.joints[j];
  const std::string name = "joint '" + js.name + "'";
  Bend b;
  b.parent = anatomical_parent(rig, g, joint);
  if (b.parent < 0) return *error = name + " is a root: a bar-net wraps the bend between two bones", false;
  if (js.dofs.empty() || js.dof_kind != rigc::DofKind::kRotation)
    return *error = name + " has no rotational degree of freedom to drive the net's loads", false;
  const size_t p = static_cast<size_t>(b.parent);
  b.c = g.frame[j].t;
  b.length = norm(sub(b.c, g.frame[p].t));
  b.u = normalized(sub(b.c, g.frame[p].t));
  if (!(norm(b.u) > 0)) b.u = g.bone_dir[p];
  int radii = 0;
  for (size_t k : {p, j})
    if (g.skin_radius[k] > 0) b.radius += g.skin_radius[k], ++radii;
  if (radii == 0) return *error = name + ": no skin vertex is weighted to it or its parent", false;
  b.radius /= radii;
  b.axis = dir_to_model(g.frame[j], js.dofs[0].axis);
  b.inner = normalized(cross(b.axis, b.u));
  b.flex_hi = js.dofs[0].max > 0 ? js.dofs[0].max : js.dofs[0].min;
  if (b.flex_hi == 0) return *error = name + ": its first DOF has no range to flex through", false;
  b.fold = b.flex_hi > 0 ? b.inner : scaled(b.inner, -1);
  b.input = 0;
  for (size_t k = 0; k < j; ++k) b.input += static_cast<int>(rig.joints[k].dofs.size());
  *out = b;
  return true;
}

std::set<int> bones_around(const rigc::RigSpec& rig, const RigGeometry& g, int joint, int parent) {
  std::set<int> bones{parent, joint};
  for (size_t k = 0; k < rig.joints.size(); ++k)
    if (rig.joints[k].parent == joint || anatomical_parent(rig, g, static_cast<int>(k)) == joint)
      bones.insert(static_cast<int>(k));
  return bones;
}

std::vector<SkinSample> skin_samples(const rigc::RigSpec& rig, const RigGeometry& g, const std::set<int>& bones,
                                     const Vec3d& c, const Vec3d& u, double max_distance, double axial_lo,
                                     double axial_hi) {
  std::vector<SkinSample> near;
  for (int b : bones)
    for (uint32_t vi : g.vertices_of[static_cast<size_t>(b)]) {
      const Vec3d rel = sub(rig.vertices[vi].position, c);
      const double axial = dot(rel, u);
      const Vec3d radial = sub(rel, scaled(u, axial));
      const double d = norm(radial);
      if (d > 0 && d <= max_distance && axial >= axial_lo && axial <= axial_hi)
        near.push_back({vi, axial, scaled(radial, 1 / d), d});
    }
  return near;
}

double skin_distance(const std::vector<SkinSample>& near, double t, const Vec3d& dir, double step, size_t* nearest) {
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
  *nearest = ranked[0].second;
  return rho / static_cast<double>(keep);
}

TubePoint skin_tube_point(const std::vector<SkinSample>& near, const Vec3d& centre, const Vec3d& u, const Vec3d& a,
                          const Vec3d& b, double t, int k, int segments, double step) {
  const double pi = 3.14159265358979323846;
  const double theta = 2 * pi * k / segments;
  const Vec3d dir = add(scaled(a, std::cos(theta)), scaled(b, std::sin(theta)));
  size_t nearest = 0;
  const double rho = skin_distance(near, t, dir, step, &nearest);
  return {add(add(centre, scaled(u, t)), scaled(dir, rho)), near[nearest].vertex};
}

}  // namespace sinew::layers::barnet
