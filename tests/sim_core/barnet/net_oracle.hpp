// Eq. (4) of barnet-driven-skinning as an oracle for any net on any rig, in
// any pose, in double (paper_eq4.hpp), in two parts:
//   - eq4_rest: the unloaded net, x = D^-1 (p0 - D_f x_f): the fixed nodes
//     x_f smoothly skinned from the bones, p0 the rest load D x0 + D_f x0_f
//     of the bind pose turned by each node's blended bones at its bind-pose
//     magnitude (barnet_model.hpp). Bound: the fixed nodes' rounding in the
//     runtime (1 LSB, moved through D^-1 D_f whose rows are convex weights),
//     the rest load's roundings (relative 2^-26, moved through ||D^-1||),
//     the solve before its final rounding (solve_bound, for the move x - s
//     the runtime solves) and the final rounding (0.5 LSB).
//   - eq4_move: a net stepped twice on the same bones, with its loads and
//     without (NetProbe): by linearity the loaded net's move from the
//     unloaded one is D^-1 p for the loads p the bones carry, up to both
//     solves' errors (solve_bound for each run's x - s, two final roundings
//     of 0.5 LSB) and the carried loads' rounding (eq4_bound: per load and
//     component, the activation's Q2.30 rounding times the force, the
//     scaling's and the bone transform's roundings), moved through ||D^-1||.
// The fine skin is then the wrap of those nodes (wrap_oracle, in double).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "paper_eq4.hpp"
#include "sim_core/barnet/barnet.hpp"

namespace sinew::test::barnet {

inline constexpr double kLenLsb = 1048576.0;  // Len LSB per rig unit

// The fixed-point solve's error before its final rounding, Len LSB, for a
// solution of largest component `largest` (Len LSB): the factor's relative
// error of 2^-30 per entry amplified by kappa_inf(D) (2^-29 with the
// solve's own products), plus one 2^-40 rig-unit rounding per product of
// the profile and per pivot (ldlt_skyline.hpp).
inline double solve_bound(const PaperSystem& sys, double largest, uint32_t profile) {
  double norm = 0;
  for (uint32_t r = 0; r < sys.free_count; ++r) {
    double row = 0;
    for (uint32_t k = 0; k < sys.free_count; ++k) row += std::abs(sys.d[r * sys.free_count + k]);
    norm = std::max(norm, row);
  }
  const double kappa = norm * paper_inverse_norm(sys);
  return kappa * 0x1p-29 * largest + (sys.free_count + 2.0 * profile) * 0x1p-20;
}

inline int32_t component(fx::Vec3 v, size_t c) { return c == 0 ? v.x : (c == 1 ? v.y : v.z); }

// A model stepped on its own arena, with or without its loads.
class NetProbe {
 public:
  NetProbe(const bn::BarnetModel& model, bool loads) : model_(model) {
    if (!loads) model_.loads = {};
    arena_.assign(bn::barnet_state_bytes(model_) / 8 + 1, 0);
    const bn::LayerStatus s = bn::barnet_init(model_, arena_.data(), arena_.size() * 8, &state_);
    if (!s.ok()) error_ = s.message;
    for (size_t c = 0; c < 3; ++c) {
      node_[c].assign(model_.nodes.size(), 0);
      skin_[c].assign(model_.wrap.size(), 0);
      out_.node[c] = node_[c];
      out_.skin[c] = skin_[c];
    }
  }
  NetProbe(const NetProbe&) = delete;
  NetProbe& operator=(const NetProbe&) = delete;
  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }
  bool step(std::span<const fx::Mat34> bones, std::span<const int32_t> angles, std::span<const int32_t> external) {
    const bn::LayerStatus s = bn::barnet_step(&state_, {bones, angles, external}, out_);
    if (!s.ok()) error_ = s.message;
    return s.ok();
  }
  const bn::BarnetModel& model() const { return model_; }
  const bn::BarnetState& state() const { return state_; }
  int32_t node(size_t c, uint32_t i) const { return node_[c][i]; }
  int32_t skin(size_t c, uint32_t w) const { return skin_[c][w]; }

 private:
  bn::BarnetModel model_;
  std::vector<uint64_t> arena_;
  bn::BarnetState state_;
  std::vector<int32_t> node_[3], skin_[3];
  bn::StepOutputs out_;
  std::string error_;
};

// A load's activation in double, as documented (barnet_model.hpp).
inline double activation(const bn::BarnetModel& m, const bn::LoadRecord& l, std::span<const int32_t> angles,
                         std::span<const int32_t> external) {
  const double v = l.input < m.input_count ? angles[l.input] : external[l.input - m.input_count];
  return std::clamp((v - l.angle_lo) / (static_cast<double>(l.angle_hi) - l.angle_lo), 0.0, 1.0);
}

// Eq. (4)'s move D^-1 p of the free nodes [c][free k] (Len LSB, unrounded)
// for the loads at their activation, carried by the runtime's skinning
// matrices (global x inverse bind, as the runtime forms them), and its bound
// against the runtime (header comment).
struct Eq4Move {
  std::vector<std::vector<double>> d;  // [c][free k]
  double bound = 0;                    // Len LSB, per free node and component
  double largest = 0;                  // max |d|
};

// solved: the largest |x - s| (Len LSB) either run solved for (the
// runtime's max_displacement), which scales each solve's error.
inline Eq4Move eq4_move(const bn::BarnetModel& m, const PaperSystem& sys, uint32_t profile, double solved,
                        std::span<const fx::Mat34> bones, std::span<const int32_t> angles,
                        std::span<const int32_t> external = {}) {
  Eq4Move r;
  r.d.assign(3, std::vector<double>(sys.free_count, 0));
  std::vector<size_t> slot(m.nodes.size(), 0);
  for (uint32_t k = 0; k < sys.free_count; ++k) slot[sys.free_nodes[k]] = k;
  std::vector<std::vector<double>> p(3, std::vector<double>(sys.free_count, 0));
  std::vector<double> error(sys.free_count, 0);  // Q8.24 LSB, per component
  for (const bn::LoadRecord& l : m.loads) {
    const double t = activation(m, l, angles, external);
    if (t == 0) continue;
    const fx::Mat34 skin = fx::mul(bones[l.joint], m.inverse_bind[l.joint]);
    double worst_row = 0, scaled_error = 0;
    for (size_t k = 0; k < 3; ++k)  // t rounded to Q2.30 (2^-31), then t f rounded (0.5 LSB); exact at t = 1
      scaled_error = std::max(scaled_error, t == 1 ? 0.0 : 0.5 + std::abs(component(l.force, k)) * 0x1p-31);
    for (size_t c = 0; c < 3; ++c) {
      double v = 0, row = 0;
      for (size_t k = 0; k < 3; ++k) {
        const double mk = std::ldexp(static_cast<double>(skin.m[c][k]), -24);
        v += mk * t * component(l.force, k);
        row += std::abs(mk);
      }
      p[c][slot[l.node]] += std::ldexp(v, -24);  // q x rig units
      worst_row = std::max(worst_row, row);
    }
    error[slot[l.node]] += 0.5 + worst_row * scaled_error;  // the transform rounds once more
  }
  for (size_t c = 0; c < 3; ++c) {
    r.d[c] = paper_solve(sys.d, p[c]);
    for (double& v : r.d[c]) {
      v *= kLenLsb;
      r.largest = std::max(r.largest, std::abs(v));
    }
  }
  const double worst_load = *std::max_element(error.begin(), error.end());  // Q8.24 LSB = 2^-4 Len LSB
  const double solve = solve_bound(sys, std::max(r.largest, solved + 1), profile);
  r.bound = 2 * (0.5 + solve) + paper_inverse_norm(sys) * worst_load / 16;
  return r;
}

// The unloaded net where eq. (4) puts it [c][free k] (Len LSB, unrounded),
// with its bound against the runtime (header comment).
struct Eq4Rest {
  std::vector<std::vector<double>> x;  // [c][free k]
  double bound = 0;                    // Len LSB, per free node and component
  double from_skinning = 0;            // largest |x - s| over free nodes and axes, s smoothly skinned
};

// q_model: the bars' compiled force densities, which the rest load is
// formed with; sys: this step's D and D_f (q scaled by its inputs).
inline Eq4Rest eq4_rest(const bn::BarnetModel& m, const PaperSystem& sys, uint32_t profile,
                        std::span<const fx::Mat34> bones) {
  const size_t n = m.nodes.size();
  std::vector<fx::Mat34> skin(m.joint_count);
  for (uint32_t j = 0; j < m.joint_count; ++j) skin[j] = fx::mul(bones[j], m.inverse_bind[j]);
  const auto linear = [&skin](uint32_t j, size_t r, size_t k) { return std::ldexp(skin[j].m[r][k], -24); };
  // Smoothly skinned positions of every node (Len LSB).
  std::vector<std::array<double, 3>> s(n);
  for (uint32_t i = 0; i < n; ++i) {
    const bn::NodeRecord& node = m.nodes[i];
    const double rest[3] = {static_cast<double>(node.rest.x), static_cast<double>(node.rest.y),
                            static_cast<double>(node.rest.z)};
    s[i] = {0, 0, 0};
    for (uint32_t k = 0; k < node.influence_count; ++k) {
      const uint32_t j = node.joint[k];
      const double w = std::ldexp(node.weight[k], -30);
      for (size_t r = 0; r < 3; ++r) {
        double v = skin[j].t[r];
        for (size_t c = 0; c < 3; ++c) v += linear(j, r, c) * rest[c];
        s[i][r] += w * v;
      }
    }
  }
  // Rest loads p0 (q x Len LSB) from the compiled q, turned by each free
  // node's blended bones, kept at |p0|.
  std::vector<std::array<double, 3>> p0(n, {0, 0, 0});
  for (const bn::BarRecord& b : m.bars) {
    const double q = std::ldexp(static_cast<double>(b.q), -16);
    const fx::Vec3 a = m.nodes[b.a].rest, c = m.nodes[b.b].rest;
    const double d[3] = {static_cast<double>(a.x) - c.x, static_cast<double>(a.y) - c.y,
                         static_cast<double>(a.z) - c.z};
    for (size_t r = 0; r < 3; ++r) {
      p0[b.a][r] += q * d[r];
      p0[b.b][r] -= q * d[r];
    }
  }
  std::vector<std::vector<double>> p(3, std::vector<double>(sys.free_count, 0));
  double largest_p0 = 0;
  for (uint32_t k = 0; k < sys.free_count; ++k) {
    const uint32_t i = sys.free_nodes[k];
    const bn::NodeRecord& node = m.nodes[i];
    double v[3] = {0, 0, 0};
    for (uint32_t h = 0; h < node.influence_count; ++h)
      for (size_t r = 0; r < 3; ++r)
        for (size_t c = 0; c < 3; ++c) v[r] += std::ldexp(node.weight[h], -30) * linear(node.joint[h], r, c) * p0[i][c];
    const double turned = std::hypot(v[0], v[1], v[2]), size = std::hypot(p0[i][0], p0[i][1], p0[i][2]);
    largest_p0 = std::max(largest_p0, size);
    for (size_t r = 0; r < 3; ++r) p[r][k] = turned > 0 ? v[r] / turned * size : 0;
  }
  Eq4Rest out;
  out.x.assign(3, std::vector<double>(sys.free_count, 0));
  for (size_t c = 0; c < 3; ++c) {
    for (uint32_t r = 0; r < sys.free_count; ++r)
      for (uint32_t k = 0; k < sys.fixed_count; ++k)
        p[c][r] -= sys.d_f[r * sys.fixed_count + k] * s[sys.fixed_nodes[k]][c];  // - D_f x_f
    out.x[c] = paper_solve(sys.d, p[c]);
    for (uint32_t k = 0; k < sys.free_count; ++k)
      out.from_skinning = std::max(out.from_skinning, std::abs(out.x[c][k] - s[sys.free_nodes[k]][c]));
  }
  out.bound =
      0.5 + 1.0 + solve_bound(sys, out.from_skinning + 2, profile) + paper_inverse_norm(sys) * largest_p0 * 0x1p-26;
  return out;
}

// The bars' force densities (Q16.16) under the net's q_inputs, as
// barnet_model.hpp documents them: q' = clamp(round(q x clamp(v, 2^-8, 2^8)),
// 2^-8, 256) per run in record order, v <= 0 reading as 1.
inline std::vector<double> scaled_q(const bn::BarnetModel& m, std::span<const int32_t> external) {
  std::vector<double> q(m.bars.size());
  for (size_t b = 0; b < q.size(); ++b) q[b] = m.bars[b].q;
  for (const bn::ForceDensityInput& r : m.q_inputs) {
    const double v = external[r.input] <= 0 ? 65536.0 : std::clamp<double>(external[r.input], 256.0, 16777216.0);
    for (uint32_t b = r.first_bar; b < r.first_bar + r.bar_count; ++b)
      q[b] = std::clamp(std::floor(q[b] * v / 65536.0 + 0.5), 256.0, 16777216.0);
  }
  return q;
}

// A net on given bones and inputs: stepped with and without its loads, and
// eq. (4) for its force densities of this step: the unloaded net's
// positions and the loads' move.
struct NetCheck {
  NetCheck(const bn::BarnetModel& m, std::span<const fx::Mat34> bones, std::span<const int32_t> angles,
           std::span<const int32_t> external)
      : loaded(m, true), unloaded(m, false), sys(paper_system(m, 1.0, scaled_q(m, external))) {
    ok = loaded.ok() && unloaded.ok() && loaded.step(bones, angles, external) && unloaded.step(bones, angles, external);
    const double solved = std::max(loaded.state().stats.max_displacement, unloaded.state().stats.max_displacement);
    move = eq4_move(m, sys, loaded.state().profile, solved, bones, angles, external);
    rest = eq4_rest(m, sys, loaded.state().profile, bones);
  }
  bool ok = false;
  NetProbe loaded, unloaded;
  PaperSystem sys;
  Eq4Move move;
  Eq4Rest rest;
};

// Largest |unloaded - eq. (4)| over the free nodes and axes (Len LSB).
inline double rest_worst(const NetCheck& n) {
  double worst = 0;
  for (uint32_t k = 0; k < n.sys.free_count; ++k)
    for (size_t c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(n.unloaded.node(c, n.sys.free_nodes[k]) - n.rest.x[c][k]));
  return worst;
}

// Largest |(loaded - unloaded) - D^-1 p| over the free nodes and axes.
inline double eq4_worst(const NetProbe& loaded, const NetProbe& unloaded, const PaperSystem& sys, const Eq4Move& e) {
  double worst = 0;
  for (uint32_t k = 0; k < sys.free_count; ++k)
    for (size_t c = 0; c < 3; ++c) {
      const uint32_t i = sys.free_nodes[k];
      worst = std::max(worst, std::abs(loaded.node(c, i) - unloaded.node(c, i) - e.d[c][k]));
    }
  return worst;
}
inline double eq4_worst(const NetCheck& n) { return eq4_worst(n.loaded, n.unloaded, n.sys, n.move); }

// Every node where eq. (4) puts it [c][node] (Len LSB, unrounded): the
// unloaded net (s, exact) plus D^-1 p on the free nodes.
inline std::vector<std::vector<double>> eq4_nodes(const NetProbe& unloaded, const PaperSystem& sys, const Eq4Move& e) {
  const size_t n = unloaded.model().nodes.size();
  std::vector<std::vector<double>> x(3, std::vector<double>(n, 0));
  for (size_t c = 0; c < 3; ++c) {
    for (uint32_t i = 0; i < n; ++i) x[c][i] = unloaded.node(c, i);
    for (uint32_t k = 0; k < sys.free_count; ++k) x[c][sys.free_nodes[k]] += e.d[c][k];
  }
  return x;
}

// The wrap of wrap entry w over nodes x [c][node] in double: bary . corners
// + offset x the unit normal of cross(c1 - c0, c2 - c0) (Len LSB).
inline std::array<double, 3> wrap_oracle(const bn::BarnetModel& m, const std::vector<std::vector<double>>& x,
                                         uint32_t w) {
  const bn::WrapRecord& r = m.wrap[w];
  const bn::ControlTriangle& t = m.triangles[r.triangle];
  double e1[3], e2[3];
  for (size_t c = 0; c < 3; ++c) {
    e1[c] = x[c][t.node[1]] - x[c][t.node[0]];
    e2[c] = x[c][t.node[2]] - x[c][t.node[0]];
  }
  const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  std::array<double, 3> out{};
  for (size_t c = 0; c < 3; ++c) {
    double v = static_cast<double>(r.offset) * n[c] / len;
    for (size_t k = 0; k < 3; ++k) v += std::ldexp(static_cast<double>(r.bary[k]), -30) * x[c][t.node[k]];
    out[c] = v;
  }
  return out;
}

// Bound on |runtime skin - wrap_oracle| for wrap entry w, per component,
// when every free node is within `node_bound` (per component) of x and the
// fixed nodes are exact: the corners' errors through |bary|, the offset
// through the normal's change under those errors (|dn| <= 2 |dc| / |c| for
// c = e1 x e2, |de| <= 2 sqrt(3) node_bound) and the runtime's normal
// quantisation (shift truncation below 2^30 and Q2.30 rounding: < 2^-26 per
// component), plus the final rounding (0.5 LSB).
inline double wrap_bound(const bn::BarnetModel& m, uint32_t free_count, const std::vector<std::vector<double>>& x,
                         double node_bound, uint32_t w) {
  const bn::WrapRecord& r = m.wrap[w];
  const bn::ControlTriangle& t = m.triangles[r.triangle];
  double corners = 0;
  for (size_t k = 0; k < 3; ++k)
    if (t.node[k] < free_count) corners += std::abs(std::ldexp(static_cast<double>(r.bary[k]), -30)) * node_bound;
  double e1[3], e2[3];
  for (size_t c = 0; c < 3; ++c) {
    e1[c] = x[c][t.node[1]] - x[c][t.node[0]];
    e2[c] = x[c][t.node[2]] - x[c][t.node[0]];
  }
  const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  const double cross = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const double l1 = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  const double l2 = std::sqrt(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]);
  const double de = 2 * std::sqrt(3.0) * node_bound;
  const double dn = 2 * (de * l2 + l1 * de + de * de) / cross + 0x1p-26;
  return 0.5 + corners + std::abs(static_cast<double>(r.offset)) * dn;
}

}  // namespace sinew::test::barnet
