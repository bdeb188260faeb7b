#include "net_spec.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <utility>

#include "host_tools/rigc/quantize.hpp"
#include "sim_core/fixed/scalar.hpp"

namespace sinew::layers::barnet {
namespace {

namespace bn = sinew::barnet;

std::string at(const char* what, size_t index, const char* field, const std::string& problem) {
  std::ostringstream s;
  s << what << "[" << index << "]." << field << ": " << problem;
  return s.str();
}

Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Squared distance from p to triangle abc (closest-point regions, Ericson's
// Real-Time Collision Detection 5.1.5).
double distance2_to_triangle(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  auto d2p = [&p](const Vec3d& q) {
    const Vec3d d = sub(p, q);
    return dot(d, d);
  };
  if (d1 <= 0 && d2 <= 0) return d2p(a);
  const Vec3d bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return d2p(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return d2p({a[0] + v * ab[0], a[1] + v * ab[1], a[2] + v * ab[2]});
  }
  const Vec3d cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return d2p(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return d2p({a[0] + w * ac[0], a[1] + w * ac[1], a[2] + w * ac[2]});
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return d2p({b[0] + w * (c[0] - b[0]), b[1] + w * (c[1] - b[1]), b[2] + w * (c[2] - b[2])});
  }
  const double denom = 1 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return d2p({a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w});
}

// Q2.30 values of w (summing to 1 in exact arithmetic) with an exact 2^30
// sum: the residue goes to the largest magnitude.
void quantize_partition(const double* w, size_t n, int32_t* out) {
  int64_t total = 0;
  size_t largest = 0;
  for (size_t i = 0; i < n; ++i) {
    out[i] = rigc::to_fixed(w[i], 30);
    total += out[i];
    if (std::fabs(w[i]) > std::fabs(w[largest])) largest = i;
  }
  out[largest] = static_cast<int32_t>(out[largest] + (fx::kUnitOne - total));
}

Vec3d rest_of(const bn::NodeRecord& n) {
  return {std::ldexp(static_cast<double>(n.rest.x), -20), std::ldexp(static_cast<double>(n.rest.y), -20),
          std::ldexp(static_cast<double>(n.rest.z), -20)};
}

// Reverse Cuthill-McKee order of the free nodes `free` (spec indices) over
// the bars joining two of them: breadth-first from a node of least degree,
// neighbours by increasing degree, each component in turn, then reversed.
// Deterministic: ties keep the spec's order.
std::vector<uint32_t> profile_order(const NetSpec& spec, const std::vector<uint32_t>& free) {
  std::vector<int> slot(spec.nodes.size(), -1);
  for (size_t k = 0; k < free.size(); ++k) slot[free[k]] = static_cast<int>(k);
  std::vector<std::vector<uint32_t>> next(free.size());
  for (const BarSpec& bar : spec.bars) {
    if (bar.a >= spec.nodes.size() || bar.b >= spec.nodes.size()) continue;  // reported by convert_bars
    const int a = slot[bar.a], b = slot[bar.b];
    if (a < 0 || b < 0 || a == b) continue;
    next[static_cast<size_t>(a)].push_back(static_cast<uint32_t>(b));
    next[static_cast<size_t>(b)].push_back(static_cast<uint32_t>(a));
  }
  for (auto& n : next) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  auto by_degree = [&next](uint32_t x, uint32_t y) {
    return next[x].size() != next[y].size() ? next[x].size() < next[y].size() : x < y;
  };
  std::vector<uint32_t> seeds(free.size());
  for (uint32_t k = 0; k < seeds.size(); ++k) seeds[k] = k;
  std::stable_sort(seeds.begin(), seeds.end(), by_degree);
  std::vector<bool> seen(free.size(), false);
  std::vector<uint32_t> order;
  for (uint32_t seed : seeds) {
    if (seen[seed]) continue;
    seen[seed] = true;
    order.push_back(seed);
    for (size_t head = order.size() - 1; head < order.size(); ++head) {
      std::vector<uint32_t> n = next[order[head]];
      std::sort(n.begin(), n.end(), by_degree);
      for (uint32_t m : n)
        if (!seen[m]) seen[m] = true, order.push_back(m);
    }
  }
  std::reverse(order.begin(), order.end());
  for (uint32_t& k : order) k = free[k];
  return order;
}

bool convert_nodes(const NetSpec& spec, const rigc::RigSpec& rig, BarnetBuild* b, std::string* error) {
  const int32_t e = b->length_exponent;
  std::vector<uint32_t> order;
  for (size_t pass = 0; pass < 2; ++pass)  // free nodes first, then fixed; stable
    for (uint32_t i = 0; i < spec.nodes.size(); ++i)
      if (spec.nodes[i].fixed == (pass == 1)) order.push_back(i);
  if (spec.profile_order) {
    const auto free_end = std::find_if(order.begin(), order.end(), [&spec](uint32_t i) { return spec.nodes[i].fixed; });
    const std::vector<uint32_t> free(order.begin(), free_end);
    const std::vector<uint32_t> ordered = profile_order(spec, free);
    std::copy(ordered.begin(), ordered.end(), order.begin());
  }
  b->node_order.assign(spec.nodes.size(), 0);
  for (uint32_t m = 0; m < order.size(); ++m) b->node_order[order[m]] = m;
  for (uint32_t m = 0; m < order.size(); ++m) {
    const uint32_t i = order[m];
    const NodeSpec& s = spec.nodes[i];
    bn::NodeRecord r;
    r.kind = static_cast<uint8_t>(s.fixed ? bn::NodeKind::kFixed : bn::NodeKind::kFree);
    r.rest = {rigc::to_len(s.rest[0], e), rigc::to_len(s.rest[1], e), rigc::to_len(s.rest[2], e)};
    if (s.influences.empty() || s.influences.size() > bn::kMaxNodeInfluences)
      return *error = at("nodes", i, "influences", "needs 1 to 4 influences"), false;
    double sum = 0;
    for (const rigc::Influence& in : s.influences) {
      if (in.palette < 0 || static_cast<size_t>(in.palette) >= rig.palette.size())
        return *error = at("nodes", i, "influences", "palette index out of range"), false;
      if (!(in.weight >= 0)) return *error = at("nodes", i, "influences", "negative or not finite weight"), false;
      sum += in.weight;
    }
    if (!(sum > 0)) return *error = at("nodes", i, "influences", "weights sum to zero"), false;
    double w[bn::kMaxNodeInfluences] = {};
    r.influence_count = static_cast<uint8_t>(s.influences.size());
    for (size_t k = 0; k < s.influences.size(); ++k) {
      r.joint[k] = static_cast<uint16_t>(rig.palette[static_cast<size_t>(s.influences[k].palette)].joint);
      w[k] = s.influences[k].weight / sum;
    }
    quantize_partition(w, s.influences.size(), r.weight);
    b->nodes.push_back(r);
  }
  return true;
}

bool convert_bars(const NetSpec& spec, BarnetBuild* b, std::string* error) {
  for (size_t i = 0; i < spec.bars.size(); ++i) {
    const BarSpec& s = spec.bars[i];
    if (s.a >= spec.nodes.size() || s.b >= spec.nodes.size()) return *error = at("bars", i, "a/b", "not a node"), false;
    if (!(s.q > 0) || !std::isfinite(s.q)) return *error = at("bars", i, "q", "force density must be positive"), false;
    const int32_t q = rigc::to_fixed(s.q, bn::kForceDensityFracBits);
    if (q < bn::kMinForceDensity || q > bn::kMaxForceDensity)
      return *error = at("bars", i, "q", "outside [2^-8, 256]"), false;
    b->bars.push_back({b->node_order[s.a], b->node_order[s.b], q});
  }
  return true;
}

bool convert_loads(const NetSpec& spec, BarnetBuild* b, std::string* error) {
  for (size_t i = 0; i < spec.loads.size(); ++i) {
    const LoadSpec& s = spec.loads[i];
    if (s.node >= spec.nodes.size()) return *error = at("loads", i, "node", "not a node"), false;
    if (spec.nodes[s.node].fixed)
      return *error = at("loads", i, "node", "a fixed node (loads act on free nodes)"), false;
    if (s.joint < 0 || static_cast<uint32_t>(s.joint) >= b->joint_count)
      return *error = at("loads", i, "joint", "not a joint"), false;
    bn::LoadRecord r;
    r.node = b->node_order[s.node];
    r.joint = static_cast<uint16_t>(s.joint);
    if (s.external_input >= 0) {
      // Driven by an external input: its index follows the joint angles in
      // the runtime's input array; lo, hi are Q16.16 values of its unit.
      if (static_cast<uint32_t>(s.external_input) >= b->external_count)
        return *error = at("loads", i, "external_input", "not an external input"), false;
      if (!(std::fabs(s.value_lo) < 32768 && std::fabs(s.value_hi) < 32768))
        return *error = at("loads", i, "value_lo/value_hi", "beyond +-32768 or not finite"), false;
      r.input = static_cast<uint16_t>(b->input_count + static_cast<uint32_t>(s.external_input));
      r.angle_lo = rigc::to_fixed(s.value_lo, 16);
      r.angle_hi = rigc::to_fixed(s.value_hi, 16);
      if (r.angle_lo == r.angle_hi) return *error = at("loads", i, "value_hi", "must differ from value_lo"), false;
    } else {
      if (s.input < 0 || static_cast<uint32_t>(s.input) >= b->input_count)
        return *error = at("loads", i, "input", "not an input"), false;
      r.input = static_cast<uint16_t>(s.input);
      r.angle_lo = rigc::to_angle(s.angle_lo);
      r.angle_hi = rigc::to_angle(s.angle_hi);
      if (r.angle_lo == r.angle_hi) return *error = at("loads", i, "angle_hi", "must differ from angle_lo"), false;
    }
    int32_t f[3];
    for (size_t c = 0; c < 3; ++c) {
      const double v = std::ldexp(s.force[c], -b->length_exponent);
      if (!(std::fabs(v) < 127.0))
        return *error = at("loads", i, "force", "beyond the Q8.24 force range or not finite"), false;
      f[c] = rigc::to_fixed(v, bn::kForceFracBits);
    }
    r.force = {f[0], f[1], f[2]};
    b->loads.push_back(r);
  }
  return true;
}

bool convert_q_inputs(const NetSpec& spec, BarnetBuild* b, std::string* error) {
  if (spec.q_inputs.size() > bn::kMaxForceDensityInputs) return *error = "q_inputs: more than 64", false;
  for (size_t i = 0; i < spec.q_inputs.size(); ++i) {
    const ForceDensityInputSpec& s = spec.q_inputs[i];
    if (s.external_input < 0 || static_cast<uint32_t>(s.external_input) >= b->external_count)
      return *error = at("q_inputs", i, "external_input", "not an external input"), false;
    if (s.bar_count == 0 || uint64_t{s.first_bar} + s.bar_count > b->bars.size())
      return *error = at("q_inputs", i, "bar_count", "an empty run or one beyond the last bar"), false;
    b->q_inputs.push_back({static_cast<uint32_t>(s.external_input), s.first_bar, s.bar_count, 0});
  }
  return true;
}

bool bind_wrap(const NetSpec& spec, const rigc::RigSpec& rig, BarnetBuild* b, std::string* error) {
  if (!spec.wrap_vertices.empty() && b->triangles.empty())
    return *error = "wrap_vertices: a wrap binding needs control triangles", false;
  for (size_t i = 0; i < spec.wrap_vertices.size(); ++i) {
    const uint32_t v = spec.wrap_vertices[i];
    if (v >= rig.vertices.size()) return *error = at("wrap_vertices", i, "", "not a skin vertex"), false;
    const rigc::Vec3d& pm = rig.vertices[v].position;
    const Vec3d p{std::ldexp(pm[0], -b->length_exponent), std::ldexp(pm[1], -b->length_exponent),
                  std::ldexp(pm[2], -b->length_exponent)};  // rig units
    uint32_t best = 0;
    double best_d2 = INFINITY;
    for (uint32_t t = 0; t < b->triangles.size(); ++t) {
      const bn::ControlTriangle& tri = b->triangles[t];
      const double d2 = distance2_to_triangle(p, rest_of(b->nodes[tri.node[0]]), rest_of(b->nodes[tri.node[1]]),
                                              rest_of(b->nodes[tri.node[2]]));
      if (d2 < best_d2) best_d2 = d2, best = t;
    }
    const bn::ControlTriangle& tri = b->triangles[best];
    const Vec3d a = rest_of(b->nodes[tri.node[0]]), bb = rest_of(b->nodes[tri.node[1]]),
                c = rest_of(b->nodes[tri.node[2]]);
    const Vec3d v0 = sub(bb, a), v1 = sub(c, a), v2 = sub(p, a);
    const Vec3d n = cross(v0, v1);
    const double n2 = dot(n, n);
    if (!(n2 > 0)) return *error = at("wrap_vertices", i, "", "closest control triangle is degenerate"), false;
    const double d00 = dot(v0, v0), d01 = dot(v0, v1), d11 = dot(v1, v1), d20 = dot(v2, v0), d21 = dot(v2, v1);
    const double denom = d00 * d11 - d01 * d01;
    const double wb = (d11 * d20 - d01 * d21) / denom, wc = (d00 * d21 - d01 * d20) / denom;
    const double w[3] = {1 - wb - wc, wb, wc};
    bn::WrapRecord r;
    r.vertex = v;
    r.triangle = best;
    quantize_partition(w, 3, r.bary);
    const double offset = dot(v2, n) / std::sqrt(n2);
    r.offset = rigc::to_fixed(offset, 20);
    b->max_wrap_offset = std::max(b->max_wrap_offset, std::fabs(std::ldexp(offset, b->length_exponent)));
    b->wrap.push_back(r);
  }
  return true;
}

}  // namespace

bn::BarnetModel BarnetBuild::model() const {
  bn::BarnetModel m;
  m.joint_count = joint_count;
  m.input_count = input_count;
  m.vertex_count = vertex_count;
  m.inverse_bind = inverse_bind;
  m.nodes = nodes;
  m.bars = bars;
  m.loads = loads;
  m.triangles = triangles;
  m.wrap = wrap;
  m.external_count = external_count;
  m.q_inputs = q_inputs;
  return m;
}

void add_tube_mesh(int rings, int segments, double q, NetSpec* net) {
  auto node = [segments](int ring, int k) { return static_cast<uint32_t>(ring * segments + (k % segments)); };
  std::set<std::pair<uint32_t, uint32_t>> edges;
  auto edge = [&edges](uint32_t a, uint32_t b) { edges.insert({a < b ? a : b, a < b ? b : a}); };
  for (int r = 0; r + 1 < rings; ++r)
    for (int k = 0; k < segments; ++k) {
      const uint32_t a = node(r, k), b = node(r, k + 1), c = node(r + 1, k), d = node(r + 1, k + 1);
      net->triangles.push_back({a, b, c});
      net->triangles.push_back({b, d, c});
      edge(a, b), edge(a, c), edge(b, c), edge(b, d), edge(d, c);
    }
  for (const auto& [a, b] : edges) net->bars.push_back({a, b, q});
}

int first_input_of(const rigc::RigSpec& rig, int joint) {
  int input = 0;
  for (int j = 0; j < joint; ++j) input += static_cast<int>(rig.joints[static_cast<size_t>(j)].dofs.size());
  return input;
}

void drive_from_inputs(const InputDrive& d, NetSpec* net) {
  if (d.force_input >= 0)
    for (LoadSpec& l : net->loads) {
      l.external_input = d.force_input;
      l.value_lo = d.value_lo;
      l.value_hi = d.value_hi;
    }
  net->external_count = d.external_count;
  if (d.q_input >= 0) net->q_inputs.push_back({d.q_input, 0, static_cast<uint32_t>(net->bars.size())});
}

bool build_barnet(const NetSpec& spec, const rigc::RigSpec& rig, BarnetBuild* out, std::string* error) {
  BarnetBuild b;
  b.length_exponent = rigc::choose_length_exponent(rig);
  b.joint_count = static_cast<uint32_t>(rig.joints.size());
  for (const rigc::JointSpec& j : rig.joints) b.input_count += static_cast<uint32_t>(j.dofs.size());
  b.vertex_count = static_cast<uint32_t>(rig.vertices.size());
  b.external_count = spec.external_count;
  if (b.external_count > bn::kMaxExternalInputs) return *error = "external_count: more than 64", false;
  // Inverse binds per joint, from the rig's palette (identity for a joint
  // the palette does not name: its skinning matrix is then its global).
  b.inverse_bind.assign(b.joint_count, fx::mat34_identity());
  for (const rigc::PaletteSpec& p : rig.palette) {
    if (p.joint < 0 || static_cast<uint32_t>(p.joint) >= b.joint_count) continue;
    fx::Mat34& m = b.inverse_bind[static_cast<size_t>(p.joint)];
    for (size_t r = 0; r < 3; ++r) {
      for (size_t c = 0; c < 3; ++c) m.m[r][c] = rigc::to_fixed(p.inverse_bind[c * 4 + r], 24);
      m.t[r] = rigc::to_len(p.inverse_bind[12 + r], b.length_exponent);
    }
  }
  if (!convert_nodes(spec, rig, &b, error) || !convert_bars(spec, &b, error) || !convert_loads(spec, &b, error) ||
      !convert_q_inputs(spec, &b, error))
    return false;
  for (size_t i = 0; i < spec.triangles.size(); ++i) {
    bn::ControlTriangle t;
    for (size_t k = 0; k < 3; ++k) {
      if (spec.triangles[i][k] >= spec.nodes.size()) return *error = at("triangles", i, "node", "not a node"), false;
      t.node[k] = b.node_order[spec.triangles[i][k]];
    }
    b.triangles.push_back(t);
  }
  if (!bind_wrap(spec, rig, &b, error)) return false;
  *out = std::move(b);
  return true;
}

}  // namespace sinew::layers::barnet
