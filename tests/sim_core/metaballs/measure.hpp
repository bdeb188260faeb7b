// Volume and cross-section measures on the built-in arm's skin tube (rings of
// kArmRingSegments vertices along +x at rest).
#pragma once

#include <array>
#include <cmath>
#include <functional>

#include "host_tools/rigc/builtin_rigs.hpp"

namespace sinew::test {

using Position = std::function<std::array<double, 3>(uint32_t)>;

inline std::array<double, 3> cross3(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dot3(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Rings whose rest x lies in [x0, x1]: [first, last].
inline bool ring_range(const rigc::RigSpec& spec, double x0, double x1, uint32_t* first, uint32_t* last) {
  const uint32_t n = rigc::kArmRingSegments, rings = static_cast<uint32_t>(spec.vertices.size()) / n;
  bool any = false;
  for (uint32_t r = 0; r < rings; ++r) {
    const double x = spec.vertices[r * n].position[0];
    if (x < x0 || x > x1) continue;
    if (!any) *first = r;
    *last = r;
    any = true;
  }
  return any;
}

// Enclosed volume of the tube between two rings, closed by fans around each
// end ring's centroid (divergence theorem: sum of signed tetrahedra).
inline double tube_volume(const Position& p, uint32_t first_ring, uint32_t last_ring) {
  const uint32_t n = rigc::kArmRingSegments;
  double six_v = 0;
  const auto tri = [&](const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c) {
    six_v += dot3(a, cross3(b, c));
  };
  const auto centroid = [&](uint32_t r) {
    std::array<double, 3> c{0, 0, 0};
    for (uint32_t k = 0; k < n; ++k)
      for (int a = 0; a < 3; ++a) c[static_cast<size_t>(a)] += p(r * n + k)[static_cast<size_t>(a)] / n;
    return c;
  };
  for (uint32_t r = first_ring; r < last_ring; ++r)
    for (uint32_t k = 0; k < n; ++k) {
      const uint32_t a = r * n + k, b = r * n + (k + 1) % n, c = a + n, d = b + n;
      tri(p(a), p(c), p(b));  // the rig's own winding (inward normals)
      tri(p(b), p(c), p(d));
    }
  const auto c0 = centroid(first_ring), c1 = centroid(last_ring);
  for (uint32_t k = 0; k < n; ++k) {
    tri(c0, p(first_ring * n + k), p(first_ring * n + (k + 1) % n));
    tri(c1, p(last_ring * n + (k + 1) % n), p(last_ring * n + k));
  }
  return std::fabs(six_v) / 6;
}

// Area of ring r's polygon in its own plane: half the vector area's length.
inline double ring_area(const Position& p, uint32_t r) {
  const uint32_t n = rigc::kArmRingSegments;
  std::array<double, 3> c{0, 0, 0}, area{0, 0, 0};
  for (uint32_t k = 0; k < n; ++k)
    for (int a = 0; a < 3; ++a) c[static_cast<size_t>(a)] += p(r * n + k)[static_cast<size_t>(a)] / n;
  for (uint32_t k = 0; k < n; ++k) {
    auto a = p(r * n + k), b = p(r * n + (k + 1) % n);
    for (int i = 0; i < 3; ++i)
      a[static_cast<size_t>(i)] -= c[static_cast<size_t>(i)], b[static_cast<size_t>(i)] -= c[static_cast<size_t>(i)];
    const auto x = cross3(a, b);
    for (int i = 0; i < 3; ++i) area[static_cast<size_t>(i)] += x[static_cast<size_t>(i)];
  }
  return 0.5 * std::sqrt(dot3(area, area));
}

}  // namespace sinew::test
