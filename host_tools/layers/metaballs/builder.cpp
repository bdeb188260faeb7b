#include "builder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "bone_pair_overlap.hpp"
#include "host_tools/layers/common/rig_geometry.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "host_tools/rigc/quantize.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "sim_core/fixed/trig.hpp"
#include "sim_core/metaballs/jiggle_gains.hpp"

namespace sinew::metaballs_build {
namespace {

namespace mb = sinew::metaballs;
using rigc::Vec3d;

constexpr int64_t kOne = fx::kUnitOne;

Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3d add(const Vec3d& a, const Vec3d& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3d mul(const Vec3d& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vec3d& a) { return std::sqrt(dot(a, a)); }
double dist(const Vec3d& a, const Vec3d& b) { return norm(sub(a, b)); }
double smoothstep(double x) {
  const double t = std::clamp(x, 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

fx::Vec3 to_len3(const Vec3d& v, int32_t e) {
  return {rigc::to_len(v[0], e), rigc::to_len(v[1], e), rigc::to_len(v[2], e)};
}
fx::Vec3 unit3(const Vec3d& v) {
  return {rigc::to_fixed(v[0], 30), rigc::to_fixed(v[1], 30), rigc::to_fixed(v[2], 30)};
}
fx::Vec3 isub(fx::Vec3 a, fx::Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }  // both within +-2^30
bool within_coords(fx::Vec3 v) {
  const int64_t lim = int64_t{1} << 30;
  return std::llabs(v.x) <= lim && std::llabs(v.y) <= lim && std::llabs(v.z) <= lim;
}
// Quantised Unit values whose sum is exactly 2^30: the largest takes the
// remainder.
std::vector<fx::Unit> quantize_weights(const std::vector<double>& w) {
  double total = 0;
  for (double x : w) total += x;
  std::vector<fx::Unit> q(w.size(), 0);
  size_t largest = 0;
  for (size_t i = 0; i < w.size(); ++i)
    if (w[i] > w[largest]) largest = i;
  int64_t rest = kOne;
  for (size_t i = 0; i < w.size(); ++i)
    if (i != largest) rest -= q[i] = rigc::to_fixed(w[i] / total, 30);
  q[largest] = static_cast<fx::Unit>(rest);
  return q;
}

std::string named(const char* what, size_t i, const char* field, const std::string& problem) {
  std::ostringstream s;
  s << what << "[" << i << "]." << field << ": " << problem;
  return s.str();
}

// Rest model transforms with the engine's own fixed-point operations, so
// T_j = model_j * inverse_bind_j is the identity at rest to rounding.
std::vector<fx::Mat34> rest_model(const rigc::RigSpec& spec, int32_t e) {
  std::vector<fx::Mat34> model(spec.joints.size());
  for (size_t j = 0; j < spec.joints.size(); ++j) {
    const rigc::JointSpec& s = spec.joints[j];
    const double n = std::sqrt(s.rotation[0] * s.rotation[0] + s.rotation[1] * s.rotation[1] +
                               s.rotation[2] * s.rotation[2] + s.rotation[3] * s.rotation[3]);
    const fx::Quat q{rigc::to_fixed(s.rotation[0] / n, 30), rigc::to_fixed(s.rotation[1] / n, 30),
                     rigc::to_fixed(s.rotation[2] / n, 30), rigc::to_fixed(s.rotation[3] / n, 30)};
    const fx::Mat34 local = fx::mat34_from_trs(
        to_len3(s.translation, e), q,
        {rigc::to_fixed(s.scale[0], 24), rigc::to_fixed(s.scale[1], 24), rigc::to_fixed(s.scale[2], 24)});
    model[j] = s.parent < 0 ? local : fx::mul(model[static_cast<size_t>(s.parent)], local);
  }
  return model;
}

// Inverse of an affine Mat34 in double (cofactors), quantised back.
bool invert(const fx::Mat34& m, fx::Mat34* out) {
  double a[3][3], t[3];
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) a[i][k] = std::ldexp(static_cast<double>(m.m[i][k]), -24);
    t[i] = std::ldexp(static_cast<double>(m.t[i]), -20);
  }
  const double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1], c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2],
               c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
  const double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
  if (!(std::fabs(det) > 1e-12)) return false;
  double inv[3][3] = {{c00, a[0][2] * a[2][1] - a[0][1] * a[2][2], a[0][1] * a[1][2] - a[0][2] * a[1][1]},
                      {c01, a[0][0] * a[2][2] - a[0][2] * a[2][0], a[0][2] * a[1][0] - a[0][0] * a[1][2]},
                      {c02, a[0][1] * a[2][0] - a[0][0] * a[2][1], a[0][0] * a[1][1] - a[0][1] * a[1][0]}};
  for (auto& row : inv)
    for (double& v : row) v /= det;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) out->m[i][k] = rigc::to_fixed(inv[i][k], 24);
    out->t[i] = rigc::to_fixed(-(inv[i][0] * t[0] + inv[i][1] * t[1] + inv[i][2] * t[2]), 20);
  }
  return true;
}

struct Geometry {
  int32_t e = 0;
  std::vector<Vec3d> joint_pos;     // model units, from the fixed rest transforms
  std::vector<fx::Vec3> joint_len;  // Len
  std::vector<Vec3d> vertex;        // model units, as quantised
  std::vector<fx::Vec3> vertex_len;
  std::vector<std::vector<double>> weight;  // [vertex][joint], normalised skin weights
  std::vector<int> dominant;
  // The skeleton as the skin sees it (layers::anatomical_parent): a joint's
  // parent is the bone it meets, even in a flat skeleton (every joint a
  // child of one unskinned root, as WebXR and many glTF hands); -1 for none.
  std::vector<int> parent, child;  // child: the first joint whose parent this is
};

struct BallSeed {
  Vec3d centre;
  int bone;
  double along;
};

int find_bone(const rigc::RigSpec& spec, const std::string& name) { return rigc::joint_index(spec, name); }

bool place_balls(const rigc::RigSpec& spec, const Geometry& g, const Options& o, std::vector<BallSeed>* seeds,
                 std::string* error) {
  const size_t nj = spec.joints.size(), nv = g.vertex.size();
  std::vector<std::vector<size_t>> verts(nj);
  for (size_t v = 0; v < nv; ++v) verts[static_cast<size_t>(g.dominant[v])].push_back(v);
  struct Segment {
    Vec3d start, end;
    bool used = false;
  };
  std::vector<Segment> seg(nj);
  double total = 0;
  for (size_t j = 0; j < nj; ++j) {
    if (verts[j].empty()) continue;
    const int child = g.child[j];
    Segment& s = seg[j];
    s.start = g.joint_pos[j];
    if (child >= 0) {
      s.end = g.joint_pos[static_cast<size_t>(child)];
    } else {
      Vec3d dir{0, 0, 0};
      const int parent = g.parent[j];
      if (parent >= 0) dir = sub(g.joint_pos[j], g.joint_pos[static_cast<size_t>(parent)]);
      if (!(norm(dir) > 1e-12)) {
        Vec3d centroid{0, 0, 0};
        for (size_t v : verts[j]) centroid = add(centroid, g.vertex[v]);
        dir = sub(mul(centroid, 1.0 / static_cast<double>(verts[j].size())), s.start);
      }
      if (!(norm(dir) > 1e-12)) continue;
      dir = mul(dir, 1.0 / norm(dir));
      double extent = 0;
      for (size_t v : verts[j]) extent = std::max(extent, dot(sub(g.vertex[v], s.start), dir));
      s.end = add(s.start, mul(dir, extent));
    }
    s.used = true;
    total += dist(s.start, s.end);
  }
  const double spacing = o.target_ball_count > 0 ? total / o.target_ball_count : o.ball_spacing;
  for (size_t j = 0; j < nj; ++j) {
    if (!seg[j].used) continue;
    const double length = dist(seg[j].start, seg[j].end);
    const int n = std::max(1, static_cast<int>(std::floor(length / spacing + 0.5)));
    for (int i = 0; i < n; ++i) {
      const double along = (i + 0.5) / n;
      seeds->push_back({add(seg[j].start, mul(sub(seg[j].end, seg[j].start), along)), static_cast<int>(j), along});
    }
  }
  if (seeds->empty()) return *error = "metaballs: no bone has skin vertices", false;
  if (seeds->size() > mb::kMaxBalls) return *error = "metaballs: more than 4096 balls (raise ball_spacing)", false;
  return true;
}

bool make_balls(const Geometry& g, const std::vector<BallSeed>& seeds, Build* b, std::vector<double>* radius,
                std::string* error) {
  const size_t nv = g.vertex.size(), nj = g.joint_pos.size();
  for (size_t i = 0; i < seeds.size(); ++i) {
    const BallSeed& s = seeds[i];
    // Only the skin of the ball's own bone (the vertices weighted to it)
    // sizes and drives the ball: where another limb's skin passes close (or
    // interpenetrates, as the built-in hand's thumb and index finger do), its
    // vertices would shrink the ball and hand it that limb's bones, and the
    // skin over it would follow the wrong bone.
    const auto own = [&](size_t v) { return g.weight[v][static_cast<size_t>(s.bone)] > 0; };
    double r = 1e300;
    for (size_t v = 0; v < nv; ++v)
      if (own(v)) r = std::min(r, dist(g.vertex[v], s.centre));
    if (!(r > 1e-9)) return *error = named("ball", i, "radius", "a vertex lies on the ball centre"), false;
    // Bone weights from the skin weights of the nearest vertices (top two
    // joints).
    std::vector<double> acc(nj, 0);
    for (size_t v = 0; v < nv; ++v)
      if (own(v) && dist(g.vertex[v], s.centre) <= 1.1 * r)
        for (size_t j = 0; j < nj; ++j) acc[j] += g.weight[v][j];
    size_t j0 = 0, j1 = nj > 1 ? 1 : 0;
    for (size_t j = 0; j < nj; ++j)
      if (acc[j] > acc[j0]) j0 = j;
    if (j1 == j0) j1 = (j0 + 1) % nj;
    for (size_t j = 0; j < nj; ++j)
      if (j != j0 && acc[j] > acc[j1]) j1 = j;
    if (!(acc[j1] > 0)) j1 = j0;
    const std::vector<fx::Unit> w =
        j1 == j0 ? std::vector<fx::Unit>{fx::kUnitOne, 0} : quantize_weights({acc[j0], acc[j1]});
    const fx::Vec3 c = to_len3(s.centre, g.e);
    if (!within_coords(c)) return *error = named("ball", i, "centre", "outside +-1024 rig units"), false;
    b->ball_rest.push_back(c);
    b->ball_radius.push_back(std::max(1, rigc::to_len(r, g.e)));
    b->ball_bone.push_back(static_cast<uint16_t>(s.bone));
    b->ball_joint.push_back(static_cast<uint16_t>(j0));
    b->ball_joint.push_back(static_cast<uint16_t>(j1));
    b->ball_weight.push_back(w[0]);
    b->ball_weight.push_back(w[1]);
    b->ball_jiggle.push_back(0);
    b->ball_along.push_back(s.along);
    radius->push_back(r);
  }
  return true;
}

bool apply_regions(const rigc::RigSpec& spec, const Options& o, Build* b, std::string* error) {
  const auto select = [&](const char* kind, size_t i, const std::string& bone, double from, double to,
                          std::vector<size_t>* balls) {
    const int j = find_bone(spec, bone);
    if (j < 0) return *error = named(kind, i, "bone", "no bone named '" + bone + "'"), false;
    for (size_t k = 0; k < b->ball_bone.size(); ++k)
      if (b->ball_bone[k] == j && b->ball_along[k] >= from && b->ball_along[k] <= to) balls->push_back(k);
    if (balls->empty()) return *error = named(kind, i, "from/to", "selects no ball of bone '" + bone + "'"), false;
    return true;
  };
  for (size_t i = 0; i < o.jiggle.size(); ++i) {
    std::vector<size_t> balls;
    if (!select("jiggle", i, o.jiggle[i].bone, o.jiggle[i].from, o.jiggle[i].to, &balls)) return false;
    for (size_t k : balls) b->ball_jiggle[k] = rigc::to_fixed(o.jiggle[i].stiffness, 30);
  }
  for (size_t i = 0; i < o.bulge.size(); ++i) {
    const BulgeRegion& r = o.bulge[i];
    std::vector<size_t> balls;
    if (!select("bulge", i, r.bone, r.from, r.to, &balls)) return false;
    const int a = find_bone(spec, r.angle_a), c = find_bone(spec, r.angle_b);
    if (a < 0) return *error = named("bulge", i, "angle_a", "no bone named '" + r.angle_a + "'"), false;
    if (c < 0) return *error = named("bulge", i, "angle_b", "no bone named '" + r.angle_b + "'"), false;
    for (size_t k : balls)
      b->bulges.push_back({static_cast<uint16_t>(k), static_cast<uint16_t>(a), static_cast<uint16_t>(c), 0,
                           rigc::to_fixed(r.gain, 30)});
  }
  return true;
}

// Jiggle in physical units: one stiffness and damping for every jiggle ball,
// from the swing frequency and W_t at the rate the model is built for.
bool apply_jiggle_gains(const Options& o, Build* b, std::string* error) {
  mb::JiggleGains gains;
  if (!mb::jiggle_gains(rigc::to_fixed(o.jiggle_frequency, 16), rigc::to_fixed(o.jiggle_window, 16), o.rate_hz, &gains))
    return *error = "jiggle_frequency/jiggle_window: the rate " + std::to_string(o.rate_hz) +
                    " Hz cannot carry this swing (need rate > 4 f and a window of several periods)",
           false;
  for (fx::Unit& k : b->ball_jiggle)
    if (k > 0) k = gains.stiffness;
  b->jiggle_damping = gains.damping;
  b->jiggle_rate_hz = o.rate_hz;
  return true;
}

// A point `at` of the way along bone j: from its joint to its first child
// (or, for a leaf, the joint itself).
Vec3d along_bone(const Geometry& g, int j, double at) {
  const int c = g.child[static_cast<size_t>(j)];
  const Vec3d& a = g.joint_pos[static_cast<size_t>(j)];
  return c < 0 ? a : add(a, mul(sub(g.joint_pos[static_cast<size_t>(c)], a), at));
}

// Action lines: the segment's rest ends, and the balls of its two bones
// within reach of it, each with its parameter and rest distance (the
// step's own integer length, so C = 0 at rest).
bool make_action_lines(const rigc::RigSpec& spec, const Geometry& g, const Options& o, Build* b, std::string* error) {
  for (size_t i = 0; i < o.action_lines.size(); ++i) {
    const ActionLineSpec& l = o.action_lines[i];
    const int jo = find_bone(spec, l.origin), ji = find_bone(spec, l.insertion);
    if (jo < 0) return *error = named("action_lines", i, "origin", "no bone named '" + l.origin + "'"), false;
    if (ji < 0) return *error = named("action_lines", i, "insertion", "no bone named '" + l.insertion + "'"), false;
    const Vec3d side{l.side[0], l.side[1], l.side[2]};
    const Vec3d po = add(along_bone(g, jo, l.origin_at), side), pi = add(along_bone(g, ji, l.insertion_at), side);
    mb::ActionLine rec{static_cast<uint16_t>(jo), static_cast<uint16_t>(ji), 0, to_len3(po, g.e), to_len3(pi, g.e)};
    if (!within_coords(rec.origin_rest) || !within_coords(rec.insertion_rest))
      return *error = named("action_lines", i, "side", "an end lies outside +-1024 rig units"), false;
    const Vec3d seg = sub(pi, po);
    const double len2 = dot(seg, seg);
    if (!(len2 > 0)) return *error = named("action_lines", i, "origin/insertion", "the line has no length"), false;
    const auto line = static_cast<uint16_t>(b->action_lines.size());
    b->action_lines.push_back(rec);
    size_t attached = 0;
    for (size_t k = 0; k < b->ball_rest.size(); ++k) {
      if (b->ball_bone[k] != jo && b->ball_bone[k] != ji) continue;
      const fx::Vec3 c = b->ball_rest[k];
      const Vec3d cd{std::ldexp(static_cast<double>(c.x), g.e - 20), std::ldexp(static_cast<double>(c.y), g.e - 20),
                     std::ldexp(static_cast<double>(c.z), g.e - 20)};
      const double t = std::min(1.0, std::max(0.0, dot(sub(cd, po), seg) / len2));
      if (!(dist(cd, add(po, mul(seg, t))) < l.reach)) continue;
      mb::ActionBall a{static_cast<uint16_t>(k), line, rigc::to_fixed(t, 30), 0, rigc::to_fixed(l.stiffness, 30)};
      // The rest distance exactly as the step measures it: the line's point
      // in integers from the quantised ends.
      const fx::Vec3 point = fx::add(rec.origin_rest, fx::scale(fx::sub(rec.insertion_rest, rec.origin_rest), a.along));
      const fx::Vec3 d = isub(c, point);
      a.rest = static_cast<fx::Len>(fx::isqrt_u64(static_cast<uint64_t>(int64_t{d.x} * d.x) +
                                                  static_cast<uint64_t>(int64_t{d.y} * d.y) +
                                                  static_cast<uint64_t>(int64_t{d.z} * d.z)));
      b->action_balls.push_back(a);
      ++attached;
    }
    if (attached == 0) return *error = named("action_lines", i, "reach", "no ball of its bones within reach"), false;
  }
  return true;
}

void make_pairs(const Options& o, const std::vector<double>& radius, const Geometry& g, Build* b) {
  const size_t n = b->ball_rest.size();
  const fx::Unit coupling =
      o.jiggle_coupling > 0 ? mb::coupling_stiffness(rigc::to_fixed(o.jiggle_coupling, 16), o.rate_hz) : 0;
  // Eq. (3) keeps a pair at its rest distance, which the skeleton's motion
  // keeps only for balls of one bone or of two bones sharing a joint; balls
  // of unrelated bones (two fingers side by side) would drag each other.
  const auto related = [&](size_t i, size_t k) {
    const int bi = b->ball_bone[i], bk = b->ball_bone[k];
    return bi == bk || g.parent[static_cast<size_t>(bi)] == bk || g.parent[static_cast<size_t>(bk)] == bi;
  };
  for (size_t i = 0; i < n; ++i)
    for (size_t k = i + 1; k < n; ++k) {
      if (!related(i, k)) continue;
      const fx::Vec3 d = isub(b->ball_rest[i], b->ball_rest[k]);
      const uint64_t n2 = static_cast<uint64_t>(int64_t{d.x} * d.x) + static_cast<uint64_t>(int64_t{d.y} * d.y) +
                          static_cast<uint64_t>(int64_t{d.z} * d.z);
      const int64_t rest = fx::isqrt_u64(n2);  // the step's own length function: C = 0 at rest
      const double reach = o.pair_reach * (radius[i] + radius[k]);
      if (rest == 0 || std::ldexp(static_cast<double>(rest), g.e - 20) >= reach) continue;
      const bool ji = b->ball_jiggle[i] > 0, jk = b->ball_jiggle[k] > 0;
      // The paper's S_out balls "are computed when the skeleton pose
      // changes", and only "the balls in S_in are modified through the
      // elasticity of springs": a pair of two skeleton-driven balls is no
      // constraint. Kept, its springs push the balls that the chord of eq.
      // (2) brings closer near a bent joint outward along the bones, and the
      // tube telescopes (2.7 points of the elbow's volume at 90 degrees).
      if (!ji && !jk) continue;
      // Physical jiggle: springs of jiggle_coupling Hz per unit mass, solved
      // by XPBD (metaballs::coupling_gains); the stiffness field carries
      // (omega_c / rate_hz)^2.
      const bool physical = o.jiggle_frequency > 0;
      if (physical && coupling == 0) continue;
      mb::BallPair p{static_cast<uint16_t>(i),
                     static_cast<uint16_t>(k),
                     static_cast<fx::Len>(rest),
                     1 << 29,
                     1 << 29,
                     physical ? coupling : rigc::to_fixed(o.jiggle_stretch_stiffness, 30)};
      if (ji != jk) {  // the kinematic ball anchors the jiggle region
        p.share_a = ji ? fx::kUnitOne : 0;
        p.share_b = ji ? 0 : fx::kUnitOne;
      }
      b->pairs.push_back(p);
    }
}

bool make_vertex_weights(const Geometry& g, const Options& o, const std::vector<double>& radius, Build* b,
                         std::string* error) {
  const size_t nv = g.vertex.size(), nb = b->ball_rest.size();
  std::vector<std::pair<double, size_t>> cand;
  for (size_t v = 0; v < nv; ++v) {
    cand.clear();
    for (size_t k = 0; k < nb; ++k)
      if (g.weight[v][b->ball_bone[k]] > 0) cand.push_back({0, k});
    if (cand.empty())
      for (size_t k = 0; k < nb; ++k) cand.push_back({0, k});
    for (auto& c : cand) {
      const fx::Vec3 cq = b->ball_rest[c.second];
      const Vec3d centre{std::ldexp(static_cast<double>(cq.x), g.e - 20),
                         std::ldexp(static_cast<double>(cq.y), g.e - 20),
                         std::ldexp(static_cast<double>(cq.z), g.e - 20)};
      c.first = std::max(1e-6, dist(g.vertex[v], centre) / radius[c.second]);
    }
    const size_t k_count = std::min<size_t>(mb::kVertexBalls, cand.size());
    std::partial_sort(cand.begin(), cand.begin() + static_cast<std::ptrdiff_t>(k_count), cand.end());
    std::vector<double> w(k_count);
    for (size_t k = 0; k < k_count; ++k) {
      double inv = 1.0 / cand[k].first, p = 1.0;
      for (int e = 0; e < o.weight_power; ++e) p *= inv;
      w[k] = p;
    }
    const std::vector<fx::Unit> q = quantize_weights(w);
    for (size_t k = 0; k < mb::kVertexBalls; ++k) {
      if (k < k_count) {
        const fx::Vec3 d = isub(g.vertex_len[v], b->ball_rest[cand[k].second]);
        if (!within_coords(d)) return *error = named("vertex", v, "displacement", "outside +-1024 rig units"), false;
        b->vertex_ball.push_back(static_cast<uint16_t>(cand[k].second));
        b->vertex_weight.push_back(q[k]);
        b->vertex_disp.push_back(d);
      } else {
        b->vertex_ball.push_back(mb::kNoBall);
        b->vertex_weight.push_back(0);
        b->vertex_disp.push_back({0, 0, 0});
      }
    }
  }
  return true;
}

std::vector<std::vector<uint32_t>> neighbours(const rigc::RigSpec& spec) {
  std::vector<std::vector<uint32_t>> n(spec.vertices.size());
  for (const auto& t : spec.triangles)
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = t[static_cast<size_t>(i)], c = t[static_cast<size_t>((i + 1) % 3)];
      if (a >= n.size() || c >= n.size()) continue;
      n[a].push_back(c);
      n[c].push_back(a);
    }
  for (auto& l : n) {
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    if (l.size() > mb::kMaxNeighbours) l.resize(mb::kMaxNeighbours);
  }
  return n;
}

// Rotates v by the unit quaternion q (w, x, y, z): v + 2 w (u x v) + 2 u x (u x v).
Vec3d rotate(const rigc::Quatd& q, const Vec3d& v) {
  const Vec3d u{q[1], q[2], q[3]};
  const auto cross = [](const Vec3d& a, const Vec3d& c) {
    return Vec3d{a[1] * c[2] - a[2] * c[1], a[2] * c[0] - a[0] * c[2], a[0] * c[1] - a[1] * c[0]};
  };
  const Vec3d t = mul(cross(u, v), 2);
  return add(add(v, mul(t, q[0])), cross(u, t));
}

// The smallest angle beta between the two bones' directions from joint j
// that its DOFs allow, as cos and sin (sin >= 0): the rest angle less the
// sum of the DOFs' largest |angle| (a DOF about bone b's own axis twists,
// it does not bend). A translation DOF, or a bend reaching the rest angle,
// folds the bones: sin = 0, cos = 1. cos and sin come from the integer
// fx::sin_cos, so the model stays bit-identical everywhere.
void tightest_fold(const rigc::RigSpec& spec, int j, const Vec3d& u_a, const Vec3d& u_b, double* cos_beta,
                   double* sin_beta) {
  rigc::Quatd q{1, 0, 0, 0};
  std::vector<int> chain;
  for (int k = j; k >= 0; k = spec.joints[static_cast<size_t>(k)].parent) chain.push_back(k);
  for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
    const rigc::Quatd& l = spec.joints[static_cast<size_t>(*it)].rotation;
    q = {q[0] * l[0] - q[1] * l[1] - q[2] * l[2] - q[3] * l[3], q[0] * l[1] + q[1] * l[0] + q[2] * l[3] - q[3] * l[2],
         q[0] * l[2] - q[1] * l[3] + q[2] * l[0] + q[3] * l[1], q[0] * l[3] + q[1] * l[2] - q[2] * l[1] + q[3] * l[0]};
  }
  const rigc::JointSpec& js = spec.joints[static_cast<size_t>(j)];
  double bend = 0;
  for (const rigc::DofSpec& d : js.dofs) {
    if (js.dof_kind != rigc::DofKind::kRotation) bend = 360;
    const Vec3d axis = rotate(q, d.axis);
    if (std::fabs(dot(axis, u_b)) > 0.999 * norm(axis)) continue;  // a twist
    bend += std::max(std::fabs(d.min), std::fabs(d.max));
  }
  // The rest angle between the bones, in degrees via the integer atan2.
  const double c0 = dot(u_a, u_b);
  const Vec3d x{u_a[1] * u_b[2] - u_a[2] * u_b[1], u_a[2] * u_b[0] - u_a[0] * u_b[2],
                u_a[0] * u_b[1] - u_a[1] * u_b[0]};
  const double s0 = norm(x);
  const fx::Angle rest = fx::atan2_angle(rigc::to_fixed(s0, 30), rigc::to_fixed(c0, 30));
  const double rest_deg = static_cast<double>(rest) / 4294967296.0 * 360.0;
  if (!(bend < rest_deg)) {
    *cos_beta = 1, *sin_beta = 0;
    return;
  }
  const fx::SinCos sc = fx::sin_cos(static_cast<fx::Angle>(rigc::to_angle(rest_deg - bend)));
  *cos_beta = std::ldexp(static_cast<double>(sc.cos), -30);
  *sin_beta = std::max(0.0, std::ldexp(static_cast<double>(sc.sin), -30));
}

bool make_joint_balls(const rigc::RigSpec& spec, const Geometry& g, const Options& o, Build* b, std::string* error) {
  const size_t nj = spec.joints.size(), nv = g.vertex.size();
  std::vector<int> joints;
  if (o.joint_balls.empty()) {
    for (size_t j = 0; j < nj; ++j)
      if (g.parent[j] >= 0 && !spec.joints[j].dofs.empty()) joints.push_back(static_cast<int>(j));
  } else {
    for (size_t i = 0; i < o.joint_balls.size(); ++i) {
      const int j = find_bone(spec, o.joint_balls[i]);
      if (j < 0) return *error = named("joint_balls", i, "name", "no joint named '" + o.joint_balls[i] + "'"), false;
      if (g.parent[static_cast<size_t>(j)] < 0)
        return *error = named("joint_balls", i, "name", "'" + o.joint_balls[i] + "' is a root: no second bone"), false;
      joints.push_back(j);
    }
  }
  struct Region {
    int joint, a, c;
    double inner, outer, surface;
  };
  std::vector<Region> regions;
  for (int j : joints) {
    const int a = g.parent[static_cast<size_t>(j)];
    double surface = 1e300;
    for (size_t v = 0; v < nv; ++v)
      if (g.dominant[v] == a || g.dominant[v] == j)
        surface = std::min(surface, dist(g.vertex[v], g.joint_pos[static_cast<size_t>(j)]));
    if (!(surface < 1e299) || !(surface > 0)) continue;  // no skin around this joint
    regions.push_back({j, a, j, o.joint_inner * surface, o.joint_outer * surface, surface});
    b->joint_balls.push_back({static_cast<uint16_t>(j), static_cast<uint16_t>(a), static_cast<uint16_t>(j), 0,
                              g.joint_len[static_cast<size_t>(j)], rigc::to_len(o.joint_outer * surface, g.e)});
  }
  const auto nbrs = neighbours(spec);
  b->jv_neighbour_begin.push_back(0);
  for (size_t v = 0; v < nv; ++v) {
    double best = 0;
    size_t best_region = 0;
    for (size_t r = 0; r < regions.size(); ++r) {
      const Region& reg = regions[r];
      if (g.dominant[v] != reg.a && g.dominant[v] != reg.c) continue;
      const double d = dist(g.vertex[v], g.joint_pos[static_cast<size_t>(reg.joint)]);
      const double alpha = smoothstep((reg.outer - d) / (reg.outer - reg.inner));
      if (alpha > best) best = alpha, best_region = r;
    }
    const fx::Unit alpha = rigc::to_fixed(best, 30);
    if (alpha < 1) continue;
    const Region& reg = regions[best_region];
    const double wa = g.weight[v][static_cast<size_t>(reg.a)], wc = g.weight[v][static_cast<size_t>(reg.c)];
    const double t = wa + wc > 0 ? wc / (wa + wc) : (g.dominant[v] == reg.c ? 1.0 : 0.0);
    b->jv_vertex.push_back(static_cast<uint32_t>(v));
    b->jv_ball.push_back(static_cast<uint16_t>(best_region));
    b->jv_alpha.push_back(alpha);
    b->jv_blend.push_back(rigc::to_fixed(t, 30));
    b->jv_disp.push_back(isub(g.vertex_len[v], g.joint_len[static_cast<size_t>(reg.joint)]));
    // Rest Laplacian with the step's own integer formula, so smoothing is a
    // no-op at rest.
    const auto& list = nbrs[v];
    const int64_t cnt = static_cast<int64_t>(list.size());
    const fx::Unit inv = cnt == 0 ? 0 : static_cast<fx::Unit>((2 * kOne + cnt) / (2 * cnt));
    int64_t sum[3] = {0, 0, 0};
    const fx::Vec3 p = g.vertex_len[v];
    for (uint32_t nb : list) {
      const fx::Vec3 q = g.vertex_len[nb];
      sum[0] += q.x - int64_t{p.x};
      sum[1] += q.y - int64_t{p.y};
      sum[2] += q.z - int64_t{p.z};
    }
    b->jv_laplacian.push_back({static_cast<int32_t>(fx::round_shift(sum[0] * inv, 30)),
                               static_cast<int32_t>(fx::round_shift(sum[1] * inv, 30)),
                               static_cast<int32_t>(fx::round_shift(sum[2] * inv, 30))});
    b->jv_inv_count.push_back(inv);
    b->jv_neighbours.insert(b->jv_neighbours.end(), list.begin(), list.end());
    b->jv_neighbour_begin.push_back(static_cast<uint32_t>(b->jv_neighbours.size()));
  }
  // Overlap candidates: per joint ball, each bone's vertices and balls near the
  // joint.
  uint64_t work = 0;
  std::vector<double> largest_radius(b->ball_rest.size());  // bulged at most by 1 + gain
  for (size_t k = 0; k < largest_radius.size(); ++k)
    largest_radius[k] = std::ldexp(static_cast<double>(b->ball_radius[k]), g.e - 20);
  for (const mb::BulgeRecord& r : b->bulges) largest_radius[r.ball] *= 1 + std::ldexp(static_cast<double>(r.gain), -30);
  for (size_t r = 0; r < regions.size(); ++r) {
    const Region& reg = regions[r];
    const Vec3d& pj = g.joint_pos[static_cast<size_t>(reg.joint)];
    const double reach = o.overlap_reach * reg.surface;
    mb::OverlapRecord rec{};
    rec.joint = static_cast<uint16_t>(reg.joint);
    rec.bone_a = static_cast<uint16_t>(reg.a);
    rec.bone_b = static_cast<uint16_t>(reg.c);
    Vec3d centroid[2] = {{0, 0, 0}, {0, 0, 0}};
    size_t count[2] = {0, 0};
    // Range-derived candidates (overlap_reach = 0): a vertex at s along its
    // bone's direction u from the joint and rho from that axis reaches the
    // other side of the interior plane at a fold beta only if
    //   s (1 - cos beta) < rho sin beta,
    // loosest at the joint's tightest fold (docs/metaballs.md); rho gets a
    // 25 % margin for the soft deformation. A ball can hold such a vertex only
    // if its centre lies within its largest (bulged) radius of one.
    const bool ranged = o.overlap_reach == 0;
    Vec3d axis[2] = {{0, 0, 0}, {0, 0, 0}};
    double cos_fold = 1, sin_fold = 0, farthest[2] = {0, 0};
    if (ranged) {
      for (int side = 0; side < 2; ++side) {
        const int bone = side == 0 ? reg.a : reg.c;
        size_t n = 0;
        for (size_t v = 0; v < nv; ++v)
          if (g.dominant[v] == bone) axis[side] = add(axis[side], g.vertex[v]), ++n;
        if (n > 0) axis[side] = sub(mul(axis[side], 1.0 / static_cast<double>(n)), pj);
        const double len = norm(axis[side]);
        if (len > 1e-12) axis[side] = mul(axis[side], 1.0 / len);
      }
      tightest_fold(spec, reg.joint, axis[0], axis[1], &cos_fold, &sin_fold);
    }
    const auto can_cross = [&](size_t v, int side) {
      if (!ranged) return dist(g.vertex[v], pj) < reach;
      const Vec3d d = sub(g.vertex[v], pj);
      const double along = dot(d, axis[side]);
      const double rho = norm(sub(d, mul(axis[side], along)));
      const bool folded_flat = cos_fold == 1 && sin_fold == 0;  // every vertex may cross
      return folded_flat || along * (1 - cos_fold) < 1.25 * rho * sin_fold;
    };
    const auto add_vertices = [&](int bone, int side) {
      for (size_t v = 0; v < nv; ++v)
        if (g.dominant[v] == bone && can_cross(v, side)) {
          farthest[side] = std::max(farthest[side], dist(g.vertex[v], pj));
          b->overlap_vertices.push_back(static_cast<uint32_t>(v));
          centroid[side] = add(centroid[side], g.vertex[v]);
          ++count[side];
        }
    };
    const auto add_balls = [&](int bone, int other_side) {
      for (size_t k = 0; k < b->ball_rest.size(); ++k) {
        const fx::Vec3 c = b->ball_rest[k];
        const Vec3d cd{std::ldexp(static_cast<double>(c.x), g.e - 20), std::ldexp(static_cast<double>(c.y), g.e - 20),
                       std::ldexp(static_cast<double>(c.z), g.e - 20)};
        const double limit = ranged ? farthest[other_side] + largest_radius[k] : reach;
        if (b->ball_bone[k] == bone && dist(cd, pj) < limit) b->overlap_balls.push_back(static_cast<uint16_t>(k));
      }
    };
    const uint32_t v0 = static_cast<uint32_t>(b->overlap_vertices.size()),
                   b0 = static_cast<uint32_t>(b->overlap_balls.size());
    add_vertices(reg.a, 0);
    uint32_t v1 = static_cast<uint32_t>(b->overlap_vertices.size());
    add_vertices(reg.c, 1);
    uint32_t v2 = static_cast<uint32_t>(b->overlap_vertices.size());
    add_balls(reg.a, 1);
    const uint32_t b1 = static_cast<uint32_t>(b->overlap_balls.size());
    add_balls(reg.c, 0);
    const uint32_t b2 = static_cast<uint32_t>(b->overlap_balls.size());
    if (count[0] == 0 || count[1] == 0) {  // one-sided joint: nothing can overlap
      b->overlap_vertices.resize(v0);
      b->overlap_balls.resize(b0);
      continue;
    }
    Vec3d dir[2];
    for (int s = 0; s < 2; ++s) {
      dir[s] = sub(mul(centroid[s], 1.0 / static_cast<double>(count[s])), pj);
      const double n = norm(dir[s]);
      if (!(n > 1e-12)) return *error = named("joint_balls", r, "overlap", "bone centroid on the joint"), false;
      dir[s] = mul(dir[s], 1.0 / n);
    }
    rec.dir_a = unit3(dir[0]);
    rec.dir_b = unit3(dir[1]);
    // A vertex already inside a ball of the other bone and beyond the
    // interior plane at rest lies where the two tissues meet in the rest
    // mesh (a knuckle inside the palm's balls): the paper's overlap is a
    // collision of the posed ball sets, and projecting it would deform the
    // rest pose, so it leaves the lists. A millimetre's thousandth of slack
    // covers the run time's rounding of the rest pose.
    const Vec3d normal = sub(dir[0], dir[1]);
    const double normal_len = norm(normal);
    const auto meets_at_rest = [&](uint32_t v, int side, uint32_t balls_begin, uint32_t balls_end) {
      if (!(normal_len > 1e-12)) return false;
      const double slack = 1e-6 * reg.surface;
      const double along = dot(sub(g.vertex[v], pj), normal) / normal_len;
      if (side == 0 ? along >= slack : along <= -slack) return false;
      for (uint32_t k = balls_begin; k < balls_end; ++k) {
        const uint16_t ball = b->overlap_balls[k];
        const fx::Vec3 c = b->ball_rest[ball];
        const Vec3d cd{std::ldexp(static_cast<double>(c.x), g.e - 20), std::ldexp(static_cast<double>(c.y), g.e - 20),
                       std::ldexp(static_cast<double>(c.z), g.e - 20)};
        if (dist(g.vertex[v], cd) < std::ldexp(static_cast<double>(b->ball_radius[ball]), g.e - 20) + slack)
          return true;
      }
      return false;
    };
    uint32_t kept = v0;
    for (uint32_t k = v0; k < v1; ++k)
      if (!meets_at_rest(b->overlap_vertices[k], 0, b1, b2)) b->overlap_vertices[kept++] = b->overlap_vertices[k];
    const uint32_t kept_a = kept;
    for (uint32_t k = v1; k < v2; ++k)
      if (!meets_at_rest(b->overlap_vertices[k], 1, b0, b1)) b->overlap_vertices[kept++] = b->overlap_vertices[k];
    b->overlap_vertices.resize(kept);
    v1 = kept_a;
    v2 = kept;
    rec.vertices_a_begin = v0, rec.vertices_a_end = v1, rec.vertices_b_begin = v1, rec.vertices_b_end = v2;
    rec.balls_a_begin = b0, rec.balls_a_end = b1, rec.balls_b_begin = b1, rec.balls_b_end = b2;
    work += uint64_t{v1 - v0} * (b2 - b1) + uint64_t{v2 - v1} * (b1 - b0);
    b->overlaps.push_back(rec);
  }
  if (work > mb::kMaxOverlapWork)
    return *error = "overlap_reach: too many vertex-ball tests per step (lower it)", false;
  // Bones that share no joint but can meet (fingers side by side).
  BonePairInput pairs_in;
  pairs_in.spec = &spec;
  pairs_in.anatomical_parent = g.parent;
  pairs_in.dominant = g.dominant;
  pairs_in.vertex_len = g.vertex_len;
  pairs_in.largest_radius.resize(largest_radius.size());
  for (size_t k = 0; k < largest_radius.size(); ++k) pairs_in.largest_radius[k] = std::ldexp(largest_radius[k], -g.e);
  const size_t joint_records = b->overlaps.size();
  if (o.overlap_between_bones && !add_bone_pair_overlaps(pairs_in, b, error)) return false;
  for (size_t r = joint_records; r < b->overlaps.size(); ++r) {
    const mb::OverlapRecord& rec = b->overlaps[r];
    const uint64_t ba = rec.balls_a_end - rec.balls_a_begin, bb = rec.balls_b_end - rec.balls_b_begin;
    work += uint64_t{rec.vertices_a_end - rec.vertices_a_begin} * bb +
            uint64_t{rec.vertices_b_end - rec.vertices_b_begin} * ba + ba * bb;
  }
  if (work > mb::kMaxOverlapWork)
    return *error =
               "metaballs: too many vertex-ball tests per step between bones that can meet (coarser "
               "ball_spacing)",
           false;
  return true;
}

}  // namespace

metaballs::MetaballModel Build::model() const {
  metaballs::MetaballModel m;
  m.joint_count = joint_count;
  m.vertex_count = vertex_count;
  m.inverse_bind = inverse_bind;
  m.ball_rest = ball_rest;
  m.ball_radius = ball_radius;
  m.ball_bone = ball_bone;
  m.ball_joint = ball_joint;
  m.ball_weight = ball_weight;
  m.ball_jiggle = ball_jiggle;
  m.pairs = pairs;
  m.action_lines = action_lines;
  m.action_balls = action_balls;
  m.bulges = bulges;
  m.pbd_iterations = pbd_iterations;
  m.jiggle_damping = jiggle_damping;
  m.jiggle_rate_hz = jiggle_rate_hz;
  m.vertex_ball = vertex_ball;
  m.vertex_weight = vertex_weight;
  m.vertex_disp = vertex_disp;
  m.joint_balls = joint_balls;
  m.jv_vertex = jv_vertex;
  m.jv_ball = jv_ball;
  m.jv_alpha = jv_alpha;
  m.jv_blend = jv_blend;
  m.jv_disp = jv_disp;
  m.jv_laplacian = jv_laplacian;
  m.jv_neighbour_begin = jv_neighbour_begin;
  m.jv_neighbours = jv_neighbours;
  m.jv_inv_count = jv_inv_count;
  m.smoothing_passes = smoothing_passes;
  m.smoothing_rate = smoothing_rate;
  m.overlaps = overlaps;
  m.overlap_vertices = overlap_vertices;
  m.overlap_balls = overlap_balls;
  return m;
}

bool build(const rigc::RigSpec& spec, const Options& o, Build* out, std::string* error) {
  if (std::string problem = check_options(o); !problem.empty()) return *error = problem, false;
  const size_t nj = spec.joints.size(), nv = spec.vertices.size();
  if (nj == 0 || nj > mb::kMaxJoints) return *error = "rig: needs 1 to 1024 joints", false;
  if (nv == 0 || nv > mb::kMaxVertices) return *error = "rig: needs 1 to 2^20 vertices", false;
  for (size_t j = 0; j < nj; ++j)
    if (spec.joints[j].parent < -1 || spec.joints[j].parent >= static_cast<int>(j))
      return *error = named("joint", j, "parent", "must be -1 or an earlier joint"), false;
  Build b;
  Geometry g;
  g.e = b.length_exponent = rigc::choose_length_exponent(spec);
  b.joint_count = static_cast<uint32_t>(nj);
  b.vertex_count = static_cast<uint32_t>(nv);
  std::vector<fx::Mat34> model = rest_model(spec, g.e);
  // A file whose bind pose (its inverse bind matrices: the mesh's space)
  // differs from its nodes' rest pose (e.g. a Z-up root): the balls live in
  // the bind space, so T_j = model_j x IBM_j maps them like the skinning.
  // Rigs whose rest pose is their bind pose keep the rest inverse exactly.
  std::vector<bool> bound(nj, false);
  std::vector<fx::Mat34> file_ibm(nj);
  for (const rigc::PaletteSpec& p : spec.palette) {
    if (p.joint < 0 || static_cast<size_t>(p.joint) >= nj || bound[static_cast<size_t>(p.joint)]) continue;
    fx::Mat34& m = file_ibm[static_cast<size_t>(p.joint)];
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) m.m[r][c] = rigc::to_fixed(p.inverse_bind[static_cast<size_t>(c * 4 + r)], 24);
      m.t[r] = rigc::to_len(p.inverse_bind[static_cast<size_t>(12 + r)], g.e);
    }
    bound[static_cast<size_t>(p.joint)] = true;
  }
  for (size_t j = 0; j < nj; ++j) {
    fx::Mat34 inv;
    if (!invert(model[j], &inv)) return *error = named("joint", j, "rest transform", "singular"), false;
    if (bound[j]) {
      int64_t worst = 0;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c)
          worst = std::max<int64_t>(worst, std::llabs(int64_t{inv.m[r][c]} - file_ibm[j].m[r][c]));
        worst = std::max<int64_t>(worst, std::llabs(int64_t{inv.t[r]} - file_ibm[j].t[r]) << 4);
      }
      if (worst > (int64_t{1} << 12)) {  // beyond 2^-12: another pose, not rounding
        fx::Mat34 bind;
        if (!invert(file_ibm[j], &bind)) return *error = named("joint", j, "inverse bind", "singular"), false;
        inv = file_ibm[j];
        model[j] = bind;
      }
    }
    b.inverse_bind.push_back(inv);
    g.joint_len.push_back({model[j].t[0], model[j].t[1], model[j].t[2]});
    g.joint_pos.push_back(
        {rigc::from_len(model[j].t[0], g.e), rigc::from_len(model[j].t[1], g.e), rigc::from_len(model[j].t[2], g.e)});
  }
  for (size_t v = 0; v < nv; ++v) {
    const rigc::VertexSpec& vs = spec.vertices[v];
    const fx::Vec3 q = to_len3(vs.position, g.e);
    if (!within_coords(q)) return *error = named("vertex", v, "position", "outside +-1024 rig units"), false;
    g.vertex_len.push_back(q);
    g.vertex.push_back({rigc::from_len(q.x, g.e), rigc::from_len(q.y, g.e), rigc::from_len(q.z, g.e)});
    std::vector<double> w(nj, 0);
    double total = 0;
    for (const rigc::Influence& in : vs.influences) {
      if (in.palette < 0 || static_cast<size_t>(in.palette) >= spec.palette.size())
        return *error = named("vertex", v, "influences", "palette index out of range"), false;
      const int j = spec.palette[static_cast<size_t>(in.palette)].joint;
      if (j < 0 || static_cast<size_t>(j) >= nj)
        return *error = named("palette", static_cast<size_t>(in.palette), "joint", "no such joint"), false;
      if (!(in.weight >= 0)) return *error = named("vertex", v, "influences", "negative or NaN weight"), false;
      w[static_cast<size_t>(j)] += in.weight;
      total += in.weight;
    }
    if (!(total > 0)) return *error = named("vertex", v, "influences", "no positive weight"), false;
    int dom = 0;
    for (size_t j = 0; j < nj; ++j) {
      w[j] /= total;
      if (w[j] > w[static_cast<size_t>(dom)]) dom = static_cast<int>(j);
    }
    // Ties go to the first-listed influence (the rig's own bone of the vertex).
    const int first = spec.palette[static_cast<size_t>(vs.influences.front().palette)].joint;
    if (w[static_cast<size_t>(first)] == w[static_cast<size_t>(dom)]) dom = first;
    g.weight.push_back(std::move(w));
    g.dominant.push_back(dom);
  }
  b.vertex_bone = g.dominant;
  {
    layers::RigGeometry rg;
    if (!layers::rig_geometry(spec, &rg, error)) return false;
    g.parent.assign(nj, -1);
    g.child.assign(nj, -1);
    for (size_t j = 0; j < nj; ++j) g.parent[j] = layers::anatomical_parent(spec, rg, static_cast<int>(j));
    for (size_t j = 0; j < nj; ++j) {
      const int p = g.parent[j];
      if (p >= 0 && g.child[static_cast<size_t>(p)] < 0) g.child[static_cast<size_t>(p)] = static_cast<int>(j);
    }
  }
  std::vector<BallSeed> seeds;
  std::vector<double> radius;
  if (!place_balls(spec, g, o, &seeds, error) || !make_balls(g, seeds, &b, &radius, error) ||
      !apply_regions(spec, o, &b, error))
    return false;
  make_pairs(o, radius, g, &b);
  if (!make_action_lines(spec, g, o, &b, error)) return false;
  if (b.pairs.size() > mb::kMaxPairs) return *error = "pair_reach: more than 32768 stretch pairs (lower it)", false;
  b.pbd_iterations = static_cast<uint32_t>(o.pbd_iterations);
  b.jiggle_damping = rigc::to_fixed(o.jiggle_damping, 30);
  // Physical gains only when a ball jiggles: a model without jiggle keeps
  // jiggle_rate_hz 0 and its bytes whatever the jiggle options say.
  const bool jiggles = std::any_of(b.ball_jiggle.begin(), b.ball_jiggle.end(), [](fx::Unit k) { return k > 0; });
  if (jiggles && o.jiggle_frequency > 0 && !apply_jiggle_gains(o, &b, error)) return false;
  if (!make_vertex_weights(g, o, radius, &b, error) || !make_joint_balls(spec, g, o, &b, error)) return false;
  b.smoothing_passes = static_cast<uint32_t>(o.smoothing_passes);
  b.smoothing_rate = rigc::to_fixed(o.smoothing_rate, 30);
  *out = std::move(b);
  return true;
}

std::string summary(const Build& b) {
  std::ostringstream s;
  s << "metaballs: " << b.ball_rest.size() << " balls, " << b.pairs.size() << " stretch pairs, " << b.bulges.size()
    << " bulging balls, " << std::count_if(b.ball_jiggle.begin(), b.ball_jiggle.end(), [](fx::Unit k) { return k > 0; })
    << " jiggle balls, " << b.joint_balls.size() << " joint balls, " << b.jv_vertex.size() << " joint-region vertices, "
    << b.overlaps.size() << " overlap joints, " << b.vertex_count << " vertices";
  return s.str();
}

}  // namespace sinew::metaballs_build
