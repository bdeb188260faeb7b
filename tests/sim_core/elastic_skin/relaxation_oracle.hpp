// A double-precision oracle of the dynamic skin's relaxation step (LEMAN
// §3, §5.3, §6.11; sim_core/elastic_skin/surface_relaxation.hpp), written
// from the equations: no fixed point, exact divisions and roots, its own
// push-out (Newton on G = F^(1/p) along the gradient) for spheres and
// single-exponent superellipsoids. The caller hands it each step's anchors,
// anchor normals, band targets and primitive frames (the upstream layers'
// outputs); positions in rig units, time in s, mass in kg.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sim_core/elastic_skin/skin_state.hpp"
#include "sim_core/muscle/muscle_state.hpp"
#include "sim_core/muscle/primitive_deform.hpp"

namespace sinew::test {

using V3 = std::array<double, 3>;
inline V3 sub3(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot3(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double norm3(const V3& a) { return std::sqrt(dot3(a, a)); }
inline V3 cross3(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double len_units(int64_t len) { return std::ldexp(double(len), -20); }
inline V3 unit_of(const fx::Vec3& u) {
  return {std::ldexp(double(u.x), -30), std::ldexp(double(u.y), -30), std::ldexp(double(u.z), -30)};
}

struct OraclePrimitive {
  V3 centre{};
  V3 axis[3]{};
  double extent[3] = {};
  int exponent = 2;  // F = sum |q_i|^p (a sphere is p = 2 with equal extents)
};

struct RelaxationOracle {
  size_t n = 0;
  double mass = 0, anchor_c = 0, band_c = 0, bend = 0, pressure = 0, omega = 0, push_back = 1, band = 0;
  int sweeps = 3, newton_steps = 3;
  std::vector<double> anchor_k, fat, ek, erest, band_k;
  std::vector<uint32_t> ea, eb, band_vertex, triangles;
  std::vector<std::vector<uint32_t>> incident, bands_at;  // edge and band indices per vertex
  V3 gravity{};
  std::vector<V3> x, v, anchor_then, band_then;
  std::vector<double> depth;  // the last step's penetration at the prediction (0: outside)
  size_t adopted = 0;         // threshold decisions taken from the runtime, all steps

  explicit RelaxationOracle(const elastic_skin::SkinModel& m) {
    n = m.vertex_count;
    mass = std::ldexp(double(m.solver.vertex_mass), -24);
    const double scale = std::ldexp(double(m.solver.stiffness_scale), -16);
    anchor_c = std::ldexp(double(m.solver.anchor_damping), -16);
    band_c = std::ldexp(double(m.solver.band_damping), -16);
    bend = std::ldexp(double(m.surface.bend), -16) * scale;
    pressure = std::ldexp(double(m.surface.pressure), -16);
    omega = 2 * M_PI * std::ldexp(double(m.surface.reaction_frequency), -16);
    sweeps = m.surface.relaxation_iterations;
    newton_steps = int(m.params.newton_steps);
    push_back = std::ldexp(double(m.params.push_back), -30);
    band = std::ldexp(double(m.params.compression_band), -30);
    gravity = {std::ldexp(double(m.solver.gravity.x), -8), std::ldexp(double(m.solver.gravity.y), -8),
               std::ldexp(double(m.solver.gravity.z), -8)};
    incident.resize(n), bands_at.resize(n);
    for (size_t i = 0; i < n; ++i) {
      anchor_k.push_back(std::ldexp(double(m.anchor_stiffness[i]), -16) * scale);
      fat.push_back(len_units(int64_t{m.fat[i]} + m.solver.fat_thickness));
    }
    for (size_t e = 0; e < m.edges.size(); ++e) {
      ea.push_back(m.edges[e].a), eb.push_back(m.edges[e].b);
      ek.push_back(std::ldexp(double(m.edges[e].k), -16) * scale);
      erest.push_back(len_units(m.edges[e].rest));
      incident[m.edges[e].a].push_back(uint32_t(e)), incident[m.edges[e].b].push_back(uint32_t(e));
    }
    for (size_t b = 0; b < m.bands.size(); ++b) {
      band_vertex.push_back(m.bands[b].vertex);
      band_k.push_back(std::ldexp(double(m.bands[b].k), -16) * scale);
      bands_at[m.bands[b].vertex].push_back(uint32_t(b));
    }
    triangles.assign(m.triangles.begin(), m.triangles.end());
  }
  uint32_t other(uint32_t e, size_t i) const { return ea[e] == i ? eb[e] : ea[e]; }
  double degree(size_t i) const { return double(incident[i].size()); }

  // Starts from the runtime's state after its first step (which settles the
  // skin statically on the first pose, then takes a step).
  void start(const elastic_skin::SkinState& st) {
    x.resize(n), v.resize(n), anchor_then.resize(n), band_then.resize(band_vertex.size());
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < 3; ++c) {
        x[i][c] = std::ldexp(double(st.fine[c][i]), -36);
        v[i][c] = std::ldexp(double(st.velocity[c][i]), -20);
        anchor_then[i][c] = len_units(st.anchor[c][i]);
      }
    for (size_t b = 0; b < band_vertex.size(); ++b)
      for (size_t c = 0; c < 3; ++c) band_then[b][c] = len_units(st.band_end[c][b]);
  }

  // §5.2: a compressed edge's stiffness multiplier.
  double push_back_factor(double excess, double rest) const {
    if (excess >= 0) return 1.0;
    const double width = band * rest;
    return width > 0 && -excess < width ? 1.0 - (1.0 - push_back) * -excess / width : push_back;
  }

  // F = sum |q_i|^p at p and its gradient (world axes).
  static double sample(const OraclePrimitive& s, const V3& p, V3* grad) {
    const V3 d = sub3(p, s.centre);
    double f = 0;
    *grad = V3{};
    for (size_t i = 0; i < 3; ++i) {
      const double q = dot3(d, s.axis[i]) / s.extent[i];
      f += std::pow(std::fabs(q), s.exponent);
      const double g = s.exponent * std::pow(std::fabs(q), s.exponent - 1) * (q < 0 ? -1 : 1) / s.extent[i];
      for (size_t c = 0; c < 3; ++c) (*grad)[c] += g * s.axis[i][c];
    }
    return f;
  }
  // Moves p out of the primitive by Newton steps on G = F^(1/p) along the
  // gradient; returns whether it was inside.
  bool push_out(const OraclePrimitive& s, V3* p) const {
    bool inside = false;
    for (int step = 0; step < newton_steps; ++step) {
      V3 grad{};
      const double f = sample(s, *p, &grad);
      if (f >= 1) break;
      inside = true;
      const double g = norm3(grad), r = std::pow(f, 1.0 / s.exponent);
      if (g == 0 || r == 0) break;
      const double delta = s.exponent * (1 - r) * f / (r * g);
      for (size_t c = 0; c < 3; ++c) (*p)[c] += delta * grad[c] / g;
    }
    return inside;
  }

  std::vector<V3> umbrella(const std::vector<V3>& a) const {
    std::vector<V3> u(n, V3{});
    for (size_t i = 0; i < n; ++i) {
      if (incident[i].empty()) continue;
      for (uint32_t e : incident[i]) {
        const uint32_t j = other(e, i);
        for (size_t c = 0; c < 3; ++c) u[i][c] += (x[j][c] - a[j][c]) / degree(i);
      }
      for (size_t c = 0; c < 3; ++c) u[i][c] -= x[i][c] - a[i][c];
    }
    return u;
  }

  // One step of h seconds to the anchors a (their normals), band targets t
  // and primitives given. Returns the vertices with a reaction floor.
  //
  // The inside test is a threshold: a fat point within rounding of a
  // primitive's surface (|F - 1| <= threshold) may be judged inside by one
  // implementation and outside by the other, and the floor of a point
  // moving in is then a whole step's inward move apart. `decided`
  // (optional, 1 inside / 0 outside per vertex) settles such points as the
  // runtime did; `adopted` counts them. Points farther from the surface are
  // the oracle's own.
  size_t step(double h, const std::vector<V3>& a, const std::vector<V3>& normals, const std::vector<V3>& t,
              const std::vector<OraclePrimitive>& prims, const std::vector<int8_t>* decided = nullptr,
              double threshold = 0) {
    const double g2 = h * h / mass, g1 = h / mass;
    std::vector<V3> x0 = x, pred(n), force(n, V3{});
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < 3; ++c) force[i][c] = mass * gravity[c];
    // §5.3: P times a third of each face's area vector, turned to its
    // corners' anchor normals, from x0.
    for (size_t f = 0; pressure != 0 && f + 2 < triangles.size(); f += 3) {
      const uint32_t p0 = triangles[f], p1 = triangles[f + 1], p2 = triangles[f + 2];
      V3 area = cross3(sub3(x0[p1], x0[p0]), sub3(x0[p2], x0[p0]));
      V3 side{};
      for (uint32_t k : {p0, p1, p2})
        for (size_t c = 0; c < 3; ++c) side[c] += normals[k][c];
      if (dot3(area, side) < 0)
        for (double& w : area) w = -w;
      for (uint32_t k : {p0, p1, p2})
        for (size_t c = 0; c < 3; ++c) force[k][c] += pressure * area[c] / 6;
    }
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < 3; ++c) pred[i][c] = x0[i][c] + h * v[i][c];
    // Platt-Barr floors at the prediction: backward Euler of the critically
    // damped law over the step.
    std::vector<V3> normal(n, V3{});
    std::vector<double> floor(n, 0);
    std::vector<bool> active(n, false);
    const double oh = omega * h;
    size_t reacting = 0;
    depth.assign(n, 0);
    for (size_t i = 0; i < n; ++i) {
      V3 p{};
      for (size_t c = 0; c < 3; ++c) p[c] = pred[i][c] - fat[i] * normals[i][c];
      const V3 start = p;
      double nearest = HUGE_VAL;  // |F - 1| of the primitive whose surface is nearest in F
      V3 nearest_grad{}, first_grad{};
      bool found = false;
      for (const OraclePrimitive& s : prims) {
        V3 grad{};
        const double f = sample(s, p, &grad);
        if (std::fabs(f - 1) < nearest) nearest = std::fabs(f - 1), nearest_grad = grad;
        if (!found && f < 1) found = true, first_grad = grad;  // §6.11's constraint gradient at the point
        push_out(s, &p);
      }
      double e0 = norm3(sub3(p, start));
      V3 direction = first_grad;
      if (decided != nullptr && nearest <= threshold && (*decided)[i] != (e0 > 0 ? 1 : 0)) {
        ++adopted;
        if ((*decided)[i] == 0) continue;
        direction = nearest_grad, e0 = 0;  // inside by the runtime: on the surface
      } else if (e0 == 0) {
        continue;
      }
      const double g = norm3(direction);
      for (size_t c = 0; c < 3; ++c) normal[i][c] = direction[c] / g;
      depth[i] = e0;
      V3 rel{};
      for (size_t c = 0; c < 3; ++c) rel[c] = (pred[i][c] - x0[i][c]) - (a[i][c] - anchor_then[i][c]);
      const double hw = dot3(normal[i], rel), e_start = e0 + hw;
      const double e_end = e_start - (hw + oh * oh * e_start) / ((1 + oh) * (1 + oh));
      floor[i] = dot3(normal[i], pred[i]) + e0 - e_end;
      active[i] = true;
      ++reacting;
    }
    // The start: K (x - x~) = (k + c)(anchor or target move - predicted move).
    x = pred;
    for (size_t i = 0; i < n; ++i) {
      double k = 1 + g1 * anchor_c + g2 * anchor_k[i];
      V3 b{};
      for (size_t c = 0; c < 3; ++c)
        b[c] = (g2 * anchor_k[i] + g1 * anchor_c) * ((a[i][c] - anchor_then[i][c]) - (pred[i][c] - x0[i][c]));
      for (uint32_t q : bands_at[i]) {
        for (size_t c = 0; c < 3; ++c)
          b[c] += (g2 * band_k[q] + g1 * band_c) * ((t[q][c] - band_then[q][c]) - (pred[i][c] - x0[i][c]));
        k += g2 * band_k[q] + g1 * band_c;
      }
      for (size_t c = 0; c < 3; ++c) x[i][c] = pred[i][c] + b[c] / k;
    }
    // The sweeps: x_i += r_i / D_i, the equation of motion times h^2 / m;
    // the umbrella vectors follow every move exactly.
    std::vector<V3> u = umbrella(a);
    for (int sweep = 0; sweep < sweeps; ++sweep) {
      for (size_t i = 0; i < n; ++i) {
        V3 r{};
        double d = 1 + g1 * anchor_c + g2 * anchor_k[i];
        for (size_t c = 0; c < 3; ++c)
          r[c] = (pred[i][c] - x[i][c]) + g2 * force[i][c] + g2 * anchor_k[i] * (a[i][c] - x[i][c]) +
                 g1 * anchor_c * ((a[i][c] - anchor_then[i][c]) - (x[i][c] - x0[i][c]));
        for (uint32_t e : incident[i]) {
          const V3 w = sub3(x[other(e, i)], x[i]);
          const double len = norm3(w);
          const double k = ek[e] * push_back_factor(len - erest[e], erest[e]);
          for (size_t c = 0; c < 3; ++c) r[c] += g2 * k * (1 - erest[e] / len) * w[c];
          d += g2 * ek[e];
        }
        for (uint32_t q : bands_at[i]) {
          for (size_t c = 0; c < 3; ++c)
            r[c] += g2 * band_k[q] * (t[q][c] - x[i][c]) +
                    g1 * band_c * ((t[q][c] - band_then[q][c]) - (x[i][c] - x0[i][c]));
          d += g2 * band_k[q] + g1 * band_c;
        }
        if (bend != 0 && !incident[i].empty()) {
          double diag = 1;
          for (uint32_t e : incident[i]) {
            const uint32_t j = other(e, i);
            diag += 1.0 / (degree(j) * degree(j));
            for (size_t c = 0; c < 3; ++c) r[c] -= g2 * bend * u[j][c] / degree(j);
          }
          for (size_t c = 0; c < 3; ++c) r[c] += g2 * bend * u[i][c];
          d += g2 * bend * diag;
        }
        V3 move{};
        for (size_t c = 0; c < 3; ++c) move[c] = r[c] / d, x[i][c] += move[c];
        if (active[i]) {
          const double lift = floor[i] - dot3(normal[i], x[i]);
          if (lift > 0)
            for (size_t c = 0; c < 3; ++c) x[i][c] += lift * normal[i][c], move[c] += lift * normal[i][c];
        }
        for (size_t c = 0; c < 3; ++c) {
          u[i][c] -= move[c];
          for (uint32_t e : incident[i]) {
            const uint32_t j = other(e, i);
            u[j][c] += move[c] / degree(j);
          }
        }
      }
    }
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < 3; ++c) v[i][c] = (x[i][c] - x0[i][c]) / h;
    anchor_then = a;
    band_then = t;
    return reacting;
  }
};

// What the upstream layers handed the runtime's skin in its last step, as
// the oracle takes it: the anchors and their normals, the band targets, the
// active primitives (spheres and single-exponent superellipsoids), the
// runtime's contact decisions and the contact threshold (a fat point within
// rounding of a surface: its position is rounded by half an LSB and its fat
// offset by one, dF/dx at the surface is at most p / (smallest extent), so
// |F - 1| below p 2 LSB / extent). `supported` is false for a primitive the
// oracle does not model (deformed, a cylinder, general exponents).
struct OracleInputs {
  std::vector<V3> anchors, normals, targets;
  std::vector<OraclePrimitive> prims;
  std::vector<int8_t> decided;
  double threshold = 0;
  bool supported = true;
};
inline OracleInputs oracle_inputs(const elastic_skin::SkinState& s, const muscle::MuscleState& m, size_t bands) {
  OracleInputs in;
  const size_t n = s.vertex_count;
  in.anchors.resize(n), in.normals.resize(n), in.targets.resize(bands), in.decided.resize(n);
  for (size_t i = 0; i < n; ++i) {
    for (size_t c = 0; c < 3; ++c) {
      in.anchors[i][c] = len_units(s.anchor[c][i]);
      in.normals[i][c] = std::ldexp(double(s.normal[c][i]), -30);
    }
    in.decided[i] = s.reaction_normal[0][i] != 0 || s.reaction_normal[1][i] != 0 || s.reaction_normal[2][i] != 0;
  }
  for (size_t b = 0; b < bands; ++b)
    for (size_t c = 0; c < 3; ++c) in.targets[b][c] = len_units(s.band_end[c][b]);
  double smallest = HUGE_VAL;
  int largest_p = 2;
  for (const muscle::PrimitiveFrame& f : m.primitives) {
    if (f.active == 0) continue;
    const bool sphere = f.kind == static_cast<uint8_t>(muscle::PrimitiveKind::kSphere);
    const bool exact = f.kind == static_cast<uint8_t>(muscle::PrimitiveKind::kSuperellipsoid) &&
                       (f.exponent == 2 || f.exponent == 4 || f.exponent == 8);
    if (muscle::is_deformed(f.deformation) || !(sphere || exact)) in.supported = false;
    OraclePrimitive p;
    p.centre = {len_units(f.centre.x), len_units(f.centre.y), len_units(f.centre.z)};
    for (size_t i = 0; i < 3; ++i) p.axis[i] = unit_of(f.axis[i]), p.extent[i] = len_units(f.extent[i]);
    p.exponent = sphere ? 2 : f.exponent;
    for (double e : p.extent) smallest = std::min(smallest, e);
    largest_p = std::max(largest_p, p.exponent);
    in.prims.push_back(p);
  }
  in.threshold = largest_p * 2 * std::ldexp(1.0, -20) / smallest;
  return in;
}

}  // namespace sinew::test
