#include "rig_geometry.hpp"

#include <algorithm>
#include <cmath>

namespace sinew::layers {

double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3d add(const Vec3d& a, const Vec3d& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3d scaled(const Vec3d& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double norm(const Vec3d& a) { return std::sqrt(dot(a, a)); }
Vec3d normalized(const Vec3d& a) {
  const double n = norm(a);
  return n > 0 ? Vec3d{a[0] / n, a[1] / n, a[2] / n} : Vec3d{0, 0, 0};
}
Vec3d perpendicular(const Vec3d& u) {
  const Vec3d helper = std::fabs(u[0]) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
  return normalized(cross(u, helper));
}

namespace {

Vec3d apply(const double m[3][3], const Vec3d& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

bool invert3(const double a[3][3], double out[3][3]) {
  const double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1], c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2],
               c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
  const double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
  if (!(std::fabs(det) > 1e-18)) return false;
  out[0][0] = c00 / det;
  out[1][0] = c01 / det;
  out[2][0] = c02 / det;
  out[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det;
  out[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det;
  out[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det;
  out[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
  out[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det;
  out[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
  return true;
}

// Rotation matrix of a quaternion (w, x, y, z), normalised first.
void rotation_of(const rigc::Quatd& q0, double r[3][3]) {
  const double n = std::sqrt(q0[0] * q0[0] + q0[1] * q0[1] + q0[2] * q0[2] + q0[3] * q0[3]);
  const double w = q0[0] / n, x = q0[1] / n, y = q0[2] / n, z = q0[3] / n;
  r[0][0] = 1 - 2 * (y * y + z * z);
  r[0][1] = 2 * (x * y - w * z);
  r[0][2] = 2 * (x * z + w * y);
  r[1][0] = 2 * (x * y + w * z);
  r[1][1] = 1 - 2 * (x * x + z * z);
  r[1][2] = 2 * (y * z - w * x);
  r[2][0] = 2 * (x * z - w * y);
  r[2][1] = 2 * (y * z + w * x);
  r[2][2] = 1 - 2 * (x * x + y * y);
}

double segment_distance(const Vec3d& p, const Vec3d& a, const Vec3d& dir, double length) {
  const Vec3d rel = sub(p, a);
  const double t = std::clamp(dot(rel, dir), 0.0, length);
  return norm(sub(rel, scaled(dir, t)));
}

}  // namespace

Vec3d to_local(const RestFrame& f, const Vec3d& p) { return apply(f.inv, sub(p, f.t)); }
Vec3d dir_to_local(const RestFrame& f, const Vec3d& d) { return normalized(apply(f.inv, d)); }
Vec3d dir_to_model(const RestFrame& f, const Vec3d& d) { return normalized(apply(f.m, d)); }

bool is_ancestor_or_self(const rigc::RigSpec& spec, int a, int b) {
  for (int j = b, steps = 0; j >= 0 && steps <= static_cast<int>(spec.joints.size());
       j = spec.joints[static_cast<size_t>(j)].parent, ++steps)
    if (j == a) return true;
  return false;
}

bool rig_geometry(const rigc::RigSpec& spec, RigGeometry* out, std::string* error) {
  const size_t nj = spec.joints.size(), nv = spec.vertices.size();
  RigGeometry g;
  g.frame.resize(nj);
  for (size_t j = 0; j < nj; ++j) {
    const rigc::JointSpec& js = spec.joints[j];
    double r[3][3], local[3][3];
    rotation_of(js.rotation, r);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) local[i][k] = r[i][k] * js.scale[static_cast<size_t>(k)];
    RestFrame& f = g.frame[j];
    if (js.parent < 0) {
      std::copy(&local[0][0], &local[0][0] + 9, &f.m[0][0]);
      f.t = js.translation;
    } else {
      const RestFrame& p = g.frame[static_cast<size_t>(js.parent)];
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
          f.m[i][k] = p.m[i][0] * local[0][k] + p.m[i][1] * local[1][k] + p.m[i][2] * local[2][k];
      f.t = add(p.t, apply(p.m, js.translation));
    }
    if (!invert3(f.m, f.inv)) return *error = "joint '" + js.name + "': degenerate rest transform (zero scale)", false;
  }
  // Skinned joints: the bind pose (the inverse of the inverse bind matrix),
  // the space the mesh is in, which a file's node rest pose need not match.
  for (const rigc::PaletteSpec& p : spec.palette) {
    if (p.joint < 0 || static_cast<size_t>(p.joint) >= nj) continue;
    const rigc::Mat4d& m = p.inverse_bind;  // column-major
    double a[3][3];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a[r][c] = m[static_cast<size_t>(c * 4 + r)];
    RestFrame f;
    if (!invert3(a, f.m))
      return *error = "joint '" + spec.joints[static_cast<size_t>(p.joint)].name + "': singular inverse bind matrix",
             false;
    std::copy(&a[0][0], &a[0][0] + 9, &f.inv[0][0]);
    const Vec3d t{m[12], m[13], m[14]};
    f.t = scaled(apply(f.m, t), -1);
    g.frame[static_cast<size_t>(p.joint)] = f;
  }
  g.first_child.assign(nj, -1);
  for (size_t j = nj; j-- > 0;)
    if (spec.joints[j].parent >= 0) g.first_child[static_cast<size_t>(spec.joints[j].parent)] = static_cast<int>(j);
  // Dominant joint per vertex: the largest summed weight over its influences.
  g.dominant.assign(nv, 0);
  g.vertices_of.assign(nj, {});
  std::vector<double> w(nj, 0.0);
  for (size_t v = 0; v < nv; ++v) {
    std::fill(w.begin(), w.end(), 0.0);
    int best = -1;
    for (const rigc::Influence& in : spec.vertices[v].influences) {
      if (in.palette < 0 || static_cast<size_t>(in.palette) >= spec.palette.size()) continue;
      const size_t j = static_cast<size_t>(spec.palette[static_cast<size_t>(in.palette)].joint);
      if (j >= nj) continue;
      w[j] += in.weight;
      if (best < 0 || w[j] > w[static_cast<size_t>(best)] ||
          (w[j] == w[static_cast<size_t>(best)] && static_cast<int>(j) < best))
        best = static_cast<int>(j);
    }
    g.dominant[v] = best < 0 ? 0 : best;
    g.vertices_of[static_cast<size_t>(g.dominant[v])].push_back(static_cast<uint32_t>(v));
  }
  g.bone_dir.assign(nj, {0, 0, 0});
  g.bone_length.assign(nj, 0.0);
  g.skin_radius.assign(nj, 0.0);
  for (size_t j = 0; j < nj; ++j) {
    const Vec3d start = g.frame[j].t;
    Vec3d dir{0, 0, 0};
    double length = 0;
    if (g.first_child[j] >= 0) {
      dir = sub(g.frame[static_cast<size_t>(g.first_child[j])].t, start);
      length = norm(dir);
    }
    // A leaf (or a joint of a flat skeleton, whose nodes all hang from one
    // root): its bone points towards the centroid of its own vertices, else
    // onward from its parent.
    if (!(length > 0) && !g.vertices_of[j].empty()) {
      Vec3d c{0, 0, 0};
      for (uint32_t v : g.vertices_of[j]) c = add(c, spec.vertices[v].position);
      dir = sub(scaled(c, 1.0 / static_cast<double>(g.vertices_of[j].size())), start);
    }
    if (!(norm(dir) > 1e-12) && spec.joints[j].parent >= 0)
      dir = sub(start, g.frame[static_cast<size_t>(spec.joints[j].parent)].t);
    if (!(norm(dir) > 0)) dir = dir_to_model(g.frame[j], {1, 0, 0});
    dir = normalized(dir);
    if (!(length > 0))  // a leaf: the bone reaches its farthest vertex along dir
      for (uint32_t v : g.vertices_of[j]) length = std::max(length, dot(sub(spec.vertices[v].position, start), dir));
    g.bone_dir[j] = dir;
    g.bone_length[j] = length;
    std::vector<double> d;
    for (uint32_t v : g.vertices_of[j]) d.push_back(segment_distance(spec.vertices[v].position, start, dir, length));
    if (!d.empty()) {
      std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
      g.skin_radius[j] = d[d.size() / 2];
    }
  }
  *out = std::move(g);
  return true;
}

int anatomical_parent(const rigc::RigSpec& spec, const RigGeometry& g, int joint) {
  const int parent = spec.joints[static_cast<size_t>(joint)].parent;
  if (parent < 0) return -1;  // a root: no bone meets it
  if (!g.vertices_of[static_cast<size_t>(parent)].empty()) return parent;
  // A flat skeleton: the skinned joint whose bone ends nearest this joint.
  const Vec3d at = g.frame[static_cast<size_t>(joint)].t;
  int best = -1;
  double best_d = 0;
  for (size_t k = 0; k < spec.joints.size(); ++k) {
    if (static_cast<int>(k) == joint || g.vertices_of[k].empty()) continue;
    const double d = norm(sub(add(g.frame[k].t, scaled(g.bone_dir[k], g.bone_length[k])), at));
    if (best < 0 || d < best_d) best = static_cast<int>(k), best_d = d;
  }
  return best >= 0 ? best : parent;  // nothing skinned elsewhere: the (unskinned) parent
}

}  // namespace sinew::layers
