// Figures measured on the arm's elbow: enclosed volume of the wrapped skin
// segment, and positions in metres.
#pragma once

#include <cmath>
#include <cstdint>

#include "host_tools/layers/barnet/arm_session.hpp"

namespace sinew::test::barnet {

using layers::barnet::ArmSession;

// Position of wrap entry w: the net's output (wrapped) or the engine's
// smooth skinning of the same vertex (baseline).
struct Point {
  double x, y, z;
};

inline Point wrapped(const ArmSession& s, uint32_t w) {
  const auto& o = s.outputs();
  return {s.metres(o.skin[0][w]), s.metres(o.skin[1][w]), s.metres(o.skin[2][w])};
}

inline Point skinned(ArmSession& s, uint32_t w) {
  const uint32_t v = s.model().wrap[w].vertex;
  const auto& p = s.engine().vertices.position;
  return {s.metres(p[0][v]), s.metres(p[1][v]), s.metres(p[2][v])};
}

inline Point rest(const ArmSession& s, uint32_t w) {
  const auto& p = s.spec().vertices[s.model().wrap[w].vertex].position;
  return {p[0], p[1], p[2]};
}

// Volume enclosed by the wrapped tube segment (its rings are consecutive
// runs of 32 wrap entries), closed by a fan at each end ring's centroid.
template <typename PointOf>
double segment_volume(const ArmSession& s, PointOf point) {
  const uint32_t n = 32, rings = static_cast<uint32_t>(s.model().wrap.size()) / n;
  double v = 0;
  auto tet = [&v](Point a, Point b, Point c) {
    v += (a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) + a.z * (b.x * c.y - b.y * c.x)) / 6;
  };
  for (uint32_t r = 0; r + 1 < rings; ++r)
    for (uint32_t k = 0; k < n; ++k) {
      const uint32_t a = r * n + k, b = r * n + (k + 1) % n, c = a + n, d = b + n;
      tet(point(a), point(c), point(b));
      tet(point(b), point(c), point(d));
    }
  for (uint32_t cap = 0; cap < 2; ++cap) {
    const uint32_t first = cap == 0 ? 0 : (rings - 1) * n;
    Point centre{0, 0, 0};
    for (uint32_t k = 0; k < n; ++k) {
      const Point p = point(first + k);
      centre = {centre.x + p.x / n, centre.y + p.y / n, centre.z + p.z / n};
    }
    for (uint32_t k = 0; k < n; ++k) {
      const Point a = point(first + k), b = point(first + (k + 1) % n);
      if (cap == 0)
        tet(centre, a, b);
      else
        tet(centre, b, a);
    }
  }
  return std::fabs(v);
}

}  // namespace sinew::test::barnet
