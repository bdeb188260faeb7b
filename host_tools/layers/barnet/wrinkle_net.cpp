#include "wrinkle_net.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "host_tools/rigc/builtin_rigs.hpp"
#include "skin_tube.hpp"

namespace sinew::layers::barnet {
namespace {

constexpr double kSkinRingStep = 0.005;  // builtin_arm's ring spacing (m)

}  // namespace

bool arm_wrinkle_net(const rigc::RigSpec& arm, const WrinkleNetOptions& o, NetSpec* out, std::string* error) {
  const int shoulder = rigc::joint_index(arm, "shoulder"), elbow = rigc::joint_index(arm, "elbow");
  const int per_ring = rigc::kArmRingSegments;
  if (shoulder < 0 || elbow < 0 || arm.vertices.size() % static_cast<size_t>(per_ring) != 0)
    return *error = "arm: not the built-in arm (joints shoulder and elbow, rings of 32 vertices)", false;
  const int r0 = static_cast<int>(std::floor(o.x_lo / kSkinRingStep + 0.5));
  const int r1 = static_cast<int>(std::floor(o.x_hi / kSkinRingStep + 0.5));
  if (r0 < 0 || r1 - r0 < 2 || r1 >= static_cast<int>(arm.vertices.size()) / per_ring)
    return *error = "x_lo/x_hi: the patch needs 3 or more skin rings on the arm", false;
  if (o.half_width < 1 || 2 * o.half_width >= per_ring) return *error = "half_width: must be 1..15", false;
  if (!(o.q > 0)) return *error = "q: must be positive", false;
  const int rings = r1 - r0 + 1, columns = 2 * o.half_width + 1;
  // Skin direction 0 is +y (the inner side); column c is direction c - half_width.
  auto vertex = [&](int ring, int column) {
    const int k = ((column - o.half_width) % per_ring + per_ring) % per_ring;
    return static_cast<uint32_t>((r0 + ring) * per_ring + k);
  };
  auto node = [columns](int ring, int column) { return static_cast<uint32_t>(ring * columns + column); };
  NetSpec s;
  for (int r = 0; r < rings; ++r)
    for (int c = 0; c < columns; ++c) {
      const rigc::VertexSpec& v = arm.vertices[vertex(r, c)];
      NodeSpec n;
      n.rest = v.position;
      n.fixed = r == 0 || r == rings - 1 || c == 0 || c == columns - 1;
      n.influences = v.influences;
      s.nodes.push_back(n);
    }
  // The skin's own triangles and edges (builtin_arm: {a, c, b}, {b, c, d}
  // per quad, a = (ring, k), b = (ring, k + 1), c = a's next ring).
  for (int r = 0; r + 1 < rings; ++r)
    for (int c = 0; c + 1 < columns; ++c) {
      const uint32_t a = node(r, c), b = node(r, c + 1), cc = node(r + 1, c), d = node(r + 1, c + 1);
      s.triangles.push_back({a, cc, b});
      s.triangles.push_back({b, cc, d});
      s.bars.push_back({a, b, o.q});
      s.bars.push_back({a, cc, o.q});
      s.bars.push_back({b, cc, o.q});
      if (c + 2 == columns) s.bars.push_back({b, d, o.q});
      if (r + 2 == rings) s.bars.push_back({cc, d, o.q});
    }
  // Creases across the arm: the normal load alternates in sign ring by
  // ring (a wavelength of two skin rings), carried by the upper arm (the
  // patch lies on its side of the crease) and activated by elbow flexion.
  for (int r = 1; r + 1 < rings; ++r)
    for (int c = 1; c + 1 < columns; ++c) {
      const rigc::VertexSpec& v = arm.vertices[vertex(r, c)];
      const double ny = v.normal[1], nz = v.normal[2], nn = std::sqrt(ny * ny + nz * nz);
      const double f = (r % 2 == 0 ? 1.0 : -1.0) * o.force;
      s.loads.push_back(
          {node(r, c), shoulder, first_input_of(arm, elbow), o.flex_lo, o.flex_hi, {0, f * ny / nn, f * nz / nn}});
      s.wrap_vertices.push_back(vertex(r, c));
    }
  *out = std::move(s);
  return true;
}

bool skin_wrinkle_net(const rigc::RigSpec& rig, const RigGeometry& g, int joint, const SkinWrinkleOptions& o,
                      NetSpec* out, std::string* error) {
  if (!(o.half_length >= 0) || !(o.force >= 0) || !(o.wavelength >= 0) || !(o.q > 0))
    return *error = "half_length, force and wavelength must be >= 0, q positive", false;
  if (!(o.half_angle == 0 || (o.half_angle >= 1 && o.half_angle <= 180)))
    return *error = "half_angle: must be 1..180 degrees (0: derived)", false;
  if (!(o.flex_lo_share >= 0 && o.flex_lo_share < 1)) return *error = "flex_lo_share: must be in [0, 1)", false;
  Bend bend;
  if (!joint_bend(rig, g, joint, &bend, error)) return false;
  const std::string name = "joint '" + rig.joints[static_cast<size_t>(joint)].name + "'";
  const double pi = 3.14159265358979323846;
  const std::set<int> bones = bones_around(rig, g, joint, bend.parent);
  // The skin's resolution at the joint: the median edge of the triangles that
  // touch its vertices within two skin radii along the bone. The default window spans at
  // least 2.5 of them each way, so that even a coarse mesh has inner
  // vertices to fold.
  std::vector<bool> near(rig.vertices.size(), false);
  for (const SkinSample& v :
       skin_samples(rig, g, bones, bend.c, bend.u, 2.5 * bend.radius, -2 * bend.radius, 2 * bend.radius))
    near[v.vertex] = true;
  std::vector<double> edges_near;
  for (const auto& t : rig.triangles)
    if (near[t[0]] || near[t[1]] || near[t[2]])
      for (size_t k = 0; k < 3; ++k)
        edges_near.push_back(norm(sub(rig.vertices[t[k]].position, rig.vertices[t[(k + 1) % 3]].position)));
  if (edges_near.empty()) return *error = name + ": no skin triangle around it", false;
  std::sort(edges_near.begin(), edges_near.end());
  const double resolution = edges_near[edges_near.size() / 2];
  const double half = o.half_length > 0 ? o.half_length : std::max(0.6 * bend.radius, 2.5 * resolution);
  const double half_angle =
      o.half_angle > 0 ? o.half_angle : std::min(180.0, std::max(60.0, 2.5 * resolution / bend.radius * 180 / pi));
  const double cos_limit = std::cos(half_angle * pi / 180);

  // The patch: skin of the bend's bones on the fold side within the window.
  std::vector<bool> in(rig.vertices.size(), false);
  for (const SkinSample& v : skin_samples(rig, g, bones, bend.c, bend.u, 2.5 * bend.radius, -half, half))
    if (dot(v.radial, bend.fold) >= cos_limit) in[v.vertex] = true;
  // Nodes: the patch's vertices that lie on a triangle inside it, welded by
  // position (copies at a seam would otherwise tear apart), in vertex order.
  std::map<std::array<double, 3>, uint32_t> at;
  std::vector<uint32_t> node_of(rig.vertices.size(), UINT32_MAX);
  std::vector<std::vector<uint32_t>> copies;
  std::vector<bool> border;
  std::vector<std::array<uint32_t, 3>> inside;
  for (const auto& t : rig.triangles)
    if (in[t[0]] && in[t[1]] && in[t[2]]) inside.push_back(t);
  std::vector<bool> used(rig.vertices.size(), false);
  for (const auto& t : inside)
    for (uint32_t v : t) used[v] = true;
  for (uint32_t v = 0; v < rig.vertices.size(); ++v) {
    if (!used[v]) continue;
    const Vec3d& p = rig.vertices[v].position;
    const auto [it, fresh] = at.insert({{p[0], p[1], p[2]}, static_cast<uint32_t>(copies.size())});
    if (fresh) copies.emplace_back(), border.push_back(false);
    node_of[v] = it->second;
    copies[it->second].push_back(v);
  }
  // A node with a triangle outside the patch is on its border: fixed.
  for (const auto& t : rig.triangles)
    if (!(in[t[0]] && in[t[1]] && in[t[2]]))
      for (uint32_t v : t)
        if (node_of[v] != UINT32_MAX) border[node_of[v]] = true;
  const uint32_t count = static_cast<uint32_t>(copies.size());
  // Triangles, bars (the edges) and area-weighted normals, welded.
  NetSpec s;
  std::set<std::pair<uint32_t, uint32_t>> edges;
  std::vector<Vec3d> normal(count, Vec3d{0, 0, 0});
  for (const auto& t : inside) {
    const uint32_t a = node_of[t[0]], b = node_of[t[1]], c = node_of[t[2]];
    if (a == b || b == c || a == c) continue;
    s.triangles.push_back({a, b, c});
    for (const auto& [x, y] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
      edges.insert({std::min(x, y), std::max(x, y)});
    const Vec3d& pa = rig.vertices[t[0]].position;
    const Vec3d n = cross(sub(rig.vertices[t[1]].position, pa), sub(rig.vertices[t[2]].position, pa));
    for (uint32_t k : {a, b, c}) normal[k] = add(normal[k], n);
  }
  std::vector<std::vector<uint32_t>> next(count);
  for (const auto& [a, b] : edges) {
    s.bars.push_back({a, b, o.q});
    next[a].push_back(b), next[b].push_back(a);
  }
  // A piece of the patch no border reaches (a closed part inside it) is held
  // fixed: its free nodes would have no path to a fixed node.
  std::vector<int> piece(count, -1);
  std::vector<bool> held;
  for (uint32_t seed = 0; seed < count; ++seed) {
    if (piece[seed] >= 0) continue;
    const int id = static_cast<int>(held.size());
    held.push_back(false);
    std::vector<uint32_t> todo{seed};
    piece[seed] = id;
    while (!todo.empty()) {
      const uint32_t k = todo.back();
      todo.pop_back();
      if (border[k]) held[static_cast<size_t>(id)] = true;
      for (uint32_t m : next[k])
        if (piece[m] < 0) piece[m] = id, todo.push_back(m);
    }
  }
  uint32_t free = 0;
  for (uint32_t k = 0; k < count; ++k) {
    NodeSpec n;
    n.rest = rig.vertices[copies[k][0]].position;
    n.fixed = border[k] || !held[static_cast<size_t>(piece[k])];
    n.influences = rig.vertices[copies[k][0]].influences;
    free += n.fixed ? 0 : 1;
    if (next[k].size() > sinew::barnet::kMaxBarsPerNode)
      return *error = name + ": a skin vertex in the wrinkle patch has more than 16 edges", false;
    s.nodes.push_back(n);
  }
  if (free == 0)
    return *error = name + ": the skin around it is too coarse for a wrinkle net (no vertex has all its triangles " +
                    "in the patch)",
           false;
  std::vector<double> lengths;
  for (const BarSpec& b : s.bars) lengths.push_back(norm(sub(s.nodes[b.a].rest, s.nodes[b.b].rest)));
  std::sort(lengths.begin(), lengths.end());
  const double edge = lengths[lengths.size() / 2];
  const double force = o.force > 0 ? o.force : 0.4 * edge;
  const double wavelength = o.wavelength > 0 ? o.wavelength : 2 * edge;
  // Creases across the bone: a normal load f cos(2 pi axial / wavelength)
  // on every free node, carried by the bone its skin follows most and
  // activated by the joint's flexion.
  for (uint32_t k = 0; k < count; ++k) {
    if (s.nodes[k].fixed) continue;
    const Vec3d rel = sub(s.nodes[k].rest, bend.c);
    const double axial = dot(rel, bend.u);
    Vec3d n = normalized(normal[k]);
    if (dot(n, sub(rel, scaled(bend.u, axial))) < 0) n = scaled(n, -1);  // outwards, whatever the winding
    const double f = force * std::cos(2 * pi * axial / wavelength);
    s.loads.push_back(
        {k, g.dominant[copies[k][0]], bend.input, o.flex_lo_share * bend.flex_hi, bend.flex_hi, scaled(n, f)});
    // Every copy of the vertex wraps its own node (the fine skin is the net).
    for (uint32_t v : copies[k]) s.wrap_vertices.push_back(v);
  }
  std::sort(s.wrap_vertices.begin(), s.wrap_vertices.end());
  *out = std::move(s);
  return true;
}

}  // namespace sinew::layers::barnet
