#include "wrinkle_net.hpp"

#include <cmath>
#include <utility>

#include "host_tools/rigc/builtin_rigs.hpp"

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

}  // namespace sinew::layers::barnet
