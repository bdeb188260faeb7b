#include "bone_pair_overlap.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace sinew::metaballs_build {
namespace {

namespace mb = sinew::metaballs;
using V = std::array<double, 3>;
using Q = std::array<double, 4>;  // w, x, y, z
struct Affine {
  double m[3][3];
  V t;
};

constexpr double kPi = 3.14159265358979323846;
// Boxes of the DOFs' ranges one pair of bones may evaluate (search_boxes);
// past it, the pairs still undecided are kept as candidates.
constexpr size_t kBoxBudget = 20000;
// Balls of two bones and blended skin move off their bone's rigid image:
// a quarter of a ball's radius more reach (as the joints' lists allow).
constexpr double kBlendMargin = 0.25;

V sub(const V& a, const V& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double norm(const V& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }
V from_len(fx::Vec3 v) {
  return {std::ldexp(static_cast<double>(v.x), -20), std::ldexp(static_cast<double>(v.y), -20),
          std::ldexp(static_cast<double>(v.z), -20)};
}

V apply(const Affine& a, const V& p) {
  V r;
  for (size_t i = 0; i < 3; ++i) r[i] = a.m[i][0] * p[0] + a.m[i][1] * p[1] + a.m[i][2] * p[2] + a.t[i];
  return r;
}

Affine compose(const Affine& a, const Affine& b) {
  Affine r{};
  for (size_t i = 0; i < 3; ++i) {
    for (size_t k = 0; k < 3; ++k) r.m[i][k] = a.m[i][0] * b.m[0][k] + a.m[i][1] * b.m[1][k] + a.m[i][2] * b.m[2][k];
    r.t[i] = a.m[i][0] * b.t[0] + a.m[i][1] * b.t[1] + a.m[i][2] * b.t[2] + a.t[i];
  }
  return r;
}

Affine identity() { return {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {0, 0, 0}}; }

Q qmul(const Q& a, const Q& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3], a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1], a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

// A joint's local transform with its rotation DOFs at `degrees` (applied
// after the rest rotation, in the joint's rest frame, as the engine does),
// translation in Len / 2^20.
Affine local(const rigc::JointSpec& j, int32_t e, const double* degrees) {
  const double n = std::sqrt(j.rotation[0] * j.rotation[0] + j.rotation[1] * j.rotation[1] +
                             j.rotation[2] * j.rotation[2] + j.rotation[3] * j.rotation[3]);
  Q q{j.rotation[0] / n, j.rotation[1] / n, j.rotation[2] / n, j.rotation[3] / n};
  for (size_t d = 0; d < j.dofs.size(); ++d) {
    const V& ax = j.dofs[d].axis;
    const double an = norm(ax), h = degrees[d] * kPi / 360.0;
    if (!(an > 0)) continue;
    q = qmul(q, {std::cos(h), std::sin(h) * ax[0] / an, std::sin(h) * ax[1] / an, std::sin(h) * ax[2] / an});
  }
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  Affine a{};
  for (size_t i = 0; i < 3; ++i) {
    for (size_t k = 0; k < 3; ++k) a.m[i][k] = r[i][k] * j.scale[k];
    a.t[i] = std::ldexp(j.translation[i], -e);
  }
  return a;
}

struct PathDof {
  int joint, dof;
  double lo, hi;     // degrees
  double lever = 0;  // largest distance of a ball of its side from the joint
  int side = 0;      // 0: bone a's chain, 1: bone b's
};

// The chain from `bone` up to (not including) `top`, bone first.
std::vector<int> chain(const rigc::RigSpec& spec, int bone, int top) {
  std::vector<int> c;
  for (int k = bone; k >= 0 && k != top; k = spec.joints[static_cast<size_t>(k)].parent) c.push_back(k);
  return c;
}

int common_ancestor(const rigc::RigSpec& spec, int a, int b) {
  std::vector<bool> above_a(spec.joints.size(), false);
  for (int k = a; k >= 0; k = spec.joints[static_cast<size_t>(k)].parent) above_a[static_cast<size_t>(k)] = true;
  for (int k = b; k >= 0; k = spec.joints[static_cast<size_t>(k)].parent)
    if (above_a[static_cast<size_t>(k)]) return k;
  return -1;
}

}  // namespace

bool add_bone_pair_overlaps(const BonePairInput& in, Build* b, std::string* error) {
  const rigc::RigSpec& spec = *in.spec;
  const size_t nj = spec.joints.size(), nb = b->ball_rest.size(), nv = in.dominant.size();
  const int32_t e = b->length_exponent;
  std::vector<std::vector<size_t>> balls_of(nj), vertices_of(nj);
  for (size_t k = 0; k < nb; ++k) balls_of[b->ball_bone[k]].push_back(k);
  for (size_t v = 0; v < nv; ++v) vertices_of[static_cast<size_t>(in.dominant[v])].push_back(v);
  std::vector<Affine> ibm(nj);
  for (size_t j = 0; j < nj; ++j) {
    for (size_t i = 0; i < 3; ++i) {
      for (size_t k = 0; k < 3; ++k) ibm[j].m[i][k] = std::ldexp(static_cast<double>(b->inverse_bind[j].m[i][k]), -24);
      ibm[j].t[i] = std::ldexp(static_cast<double>(b->inverse_bind[j].t[i]), -20);
    }
  }
  std::vector<V> centre(nb);
  std::vector<double> rest_radius(nb), reach(nb);
  for (size_t k = 0; k < nb; ++k) {
    centre[k] = from_len(b->ball_rest[k]);
    rest_radius[k] = std::ldexp(static_cast<double>(b->ball_radius[k]), -20);
    reach[k] = in.largest_radius[k] + kBlendMargin * rest_radius[k];
  }
  for (size_t a = 0; a < nj; ++a)
    for (size_t c = a + 1; c < nj; ++c) {
      if (balls_of[a].empty() || balls_of[c].empty() || vertices_of[a].empty() || vertices_of[c].empty()) continue;
      if (in.anatomical_parent[a] == static_cast<int>(c) || in.anatomical_parent[c] == static_cast<int>(a))
        continue;  // the joint's own record
      const int top = common_ancestor(spec, static_cast<int>(a), static_cast<int>(c));
      const std::vector<int> sides[2] = {chain(spec, static_cast<int>(a), top), chain(spec, static_cast<int>(c), top)};
      const size_t bone[2] = {a, c};
      // The chains relative to the common ancestor (which moves both alike):
      // T_bone = chain * IBM_bone, from the chain's top down.
      const auto posed = [&](int s, const std::vector<double>& degrees) {
        Affine t = identity();
        for (auto it = sides[s].rbegin(); it != sides[s].rend(); ++it)
          t = compose(t, local(spec.joints[static_cast<size_t>(*it)], e, &degrees[3 * static_cast<size_t>(*it)]));
        return compose(t, ibm[bone[s]]);
      };
      std::vector<PathDof> dofs;
      bool translates = false;
      for (int s = 0; s < 2; ++s)
        for (int j : sides[s]) {
          const rigc::JointSpec& js = spec.joints[static_cast<size_t>(j)];
          if (js.dof_kind != rigc::DofKind::kRotation && !js.dofs.empty()) translates = true;
          for (size_t d = 0; d < js.dofs.size(); ++d)
            dofs.push_back({j, static_cast<int>(d), std::min(js.dofs[d].min, js.dofs[d].max),
                            std::max(js.dofs[d].min, js.dofs[d].max), 0, s});
        }
      // Rest: distances of the balls from the path's joints (the same in
      // every pose: both are carried by the chain below the joint).
      std::vector<double> degrees(3 * nj, 0.0);
      const Affine rest[2] = {posed(0, degrees), posed(1, degrees)};
      std::vector<V> joint_rest(nj);
      for (int s = 0; s < 2; ++s) {
        Affine t = identity();
        for (auto it = sides[s].rbegin(); it != sides[s].rend(); ++it) {
          t = compose(t, local(spec.joints[static_cast<size_t>(*it)], e, &degrees[3 * static_cast<size_t>(*it)]));
          joint_rest[static_cast<size_t>(*it)] = t.t;
        }
      }
      for (PathDof& d : dofs)
        for (size_t k : balls_of[bone[d.side]])
          d.lever =
              std::max(d.lever, norm(sub(apply(rest[d.side], centre[k]), joint_rest[static_cast<size_t>(d.joint)])));
      std::vector<std::vector<double>> arm(dofs.size(),
                                           std::vector<double>(nb, 0.0));  // ball's distance from the DOF's joint
      for (size_t i = 0; i < dofs.size(); ++i)
        for (size_t k : balls_of[bone[dofs[i].side]])
          arm[i][k] = norm(sub(apply(rest[dofs[i].side], centre[k]), joint_rest[static_cast<size_t>(dofs[i].joint)]));
      // Candidate ball pairs: apart at rest (touching there, they are one
      // tissue) and within reach somewhere in the DOFs' box (every pair, if a
      // DOF translates).
      const size_t na = balls_of[a].size(), nc = balls_of[c].size();
      std::vector<bool> candidate(na * nc, false);
      std::vector<uint32_t> open;
      for (size_t i = 0; i < na; ++i)
        for (size_t k = 0; k < nc; ++k) {
          const size_t bi = balls_of[a][i], bk = balls_of[c][k];
          const bool apart =
              norm(sub(apply(rest[0], centre[bi]), apply(rest[1], centre[bk]))) >= rest_radius[bi] + rest_radius[bk];
          if (apart && translates) candidate[i * nc + k] = true;
          if (apart && !translates) open.push_back(static_cast<uint32_t>(i * nc + k));
        }
      // Branch and bound over the box of the DOFs' ranges: at a box's centre
      // pose a ball is within sum_d half-width_d x (its distance from DOF d's
      // joint) of where any pose of the box puts it (each rotation moves it
      // by at most that angle times that distance). A pair farther apart than
      // both reaches and both margins cannot meet in the box; one within
      // reach at the centre is a candidate; the rest split the box along the
      // DOF that moves the balls most, down to a millimetre-scale margin.
      struct Box {
        std::vector<double> lo, hi;
        std::vector<uint32_t> open;
      };
      std::vector<Box> stack;
      if (!open.empty()) {
        Box whole;
        for (const PathDof& d : dofs) whole.lo.push_back(d.lo), whole.hi.push_back(d.hi);
        whole.open = open;
        stack.push_back(std::move(whole));
      }
      size_t boxes = 0;
      std::vector<V> pa(na), pc(nc);
      std::vector<double> ma(na), mc(nc);
      while (!stack.empty()) {
        Box box = std::move(stack.back());
        stack.pop_back();
        std::vector<uint32_t> still;
        for (uint32_t p : box.open)
          if (!candidate[p]) still.push_back(p);
        if (still.empty()) continue;
        if (++boxes > kBoxBudget) {  // past the budget: keep them all
          for (uint32_t p : still) candidate[p] = true;
          continue;
        }
        for (size_t i = 0; i < dofs.size(); ++i)
          degrees[3 * static_cast<size_t>(dofs[i].joint) + static_cast<size_t>(dofs[i].dof)] =
              (box.lo[i] + box.hi[i]) / 2;
        const Affine ta = posed(0, degrees), tc = posed(1, degrees);
        for (size_t i = 0; i < na; ++i) pa[i] = apply(ta, centre[balls_of[a][i]]), ma[i] = 0;
        for (size_t k = 0; k < nc; ++k) pc[k] = apply(tc, centre[balls_of[c][k]]), mc[k] = 0;
        size_t widest = 0;
        double widest_move = 0, largest_margin = 0;
        for (size_t d = 0; d < dofs.size(); ++d) {
          const double half = (box.hi[d] - box.lo[d]) / 2 * kPi / 180.0;
          if (half * dofs[d].lever > widest_move) widest_move = half * dofs[d].lever, widest = d;
          for (size_t i = 0; i < na; ++i) ma[i] += half * arm[d][balls_of[a][i]];
          for (size_t k = 0; k < nc; ++k) mc[k] += half * arm[d][balls_of[c][k]];
        }
        std::vector<uint32_t> ambiguous;
        for (uint32_t p : still) {
          const size_t i = p / nc, k = p % nc, bi = balls_of[a][i], bk = balls_of[c][k];
          const double gap = norm(sub(pa[i], pc[k])) - reach[bi] - reach[bk];
          if (gap < 0) {
            candidate[p] = true;
          } else if (gap < ma[i] + mc[k]) {
            ambiguous.push_back(p);
            largest_margin = std::max(largest_margin, ma[i] + mc[k]);
          }
        }
        if (ambiguous.empty()) continue;
        // Small enough: a margin below half the smallest reach involved.
        double smallest = 1e300;
        for (uint32_t p : ambiguous)
          smallest = std::min({smallest, reach[balls_of[a][p / nc]], reach[balls_of[c][p % nc]]});
        if (largest_margin < 2.0 * smallest) {
          for (uint32_t p : ambiguous) candidate[p] = true;
          continue;
        }
        Box lower{box.lo, box.hi, ambiguous}, upper{box.lo, box.hi, std::move(ambiguous)};
        const double mid = (box.lo[widest] + box.hi[widest]) / 2;
        lower.hi[widest] = mid;
        upper.lo[widest] = mid;
        stack.push_back(std::move(lower));
        stack.push_back(std::move(upper));
      }
      // A vertex of one bone inside ball k of the other, which collides with
      // ball i of its own, lies within r_i + 2 r_k of ball i (the triangle
      // inequality), measured on its own bone at rest.
      const auto near_own_ball = [&](size_t v, int s) {
        const V p = from_len(in.vertex_len[v]);
        for (size_t i = 0; i < na; ++i)
          for (size_t k = 0; k < nc; ++k) {
            if (!candidate[i * nc + k]) continue;
            const size_t own = s == 0 ? balls_of[a][i] : balls_of[c][k];
            const size_t other = s == 0 ? balls_of[c][k] : balls_of[a][i];
            if (norm(sub(p, centre[own])) < reach[own] + 2 * reach[other]) return true;
          }
        return false;
      };
      if (std::none_of(candidate.begin(), candidate.end(), [](bool x) { return x; })) continue;
      mb::OverlapRecord rec{};
      rec.joint = mb::kNoJoint;
      rec.bone_a = static_cast<uint16_t>(a);
      rec.bone_b = static_cast<uint16_t>(c);
      rec.vertices_a_begin = static_cast<uint32_t>(b->overlap_vertices.size());
      for (size_t v : vertices_of[a])
        if (near_own_ball(v, 0)) b->overlap_vertices.push_back(static_cast<uint32_t>(v));
      rec.vertices_a_end = rec.vertices_b_begin = static_cast<uint32_t>(b->overlap_vertices.size());
      for (size_t v : vertices_of[c])
        if (near_own_ball(v, 1)) b->overlap_vertices.push_back(static_cast<uint32_t>(v));
      rec.vertices_b_end = static_cast<uint32_t>(b->overlap_vertices.size());
      // Each side's balls that take part in a candidate pair.
      rec.balls_a_begin = static_cast<uint32_t>(b->overlap_balls.size());
      for (size_t i = 0; i < na; ++i)
        for (size_t k = 0; k < nc; ++k)
          if (candidate[i * nc + k]) {
            b->overlap_balls.push_back(static_cast<uint16_t>(balls_of[a][i]));
            break;
          }
      rec.balls_a_end = rec.balls_b_begin = static_cast<uint32_t>(b->overlap_balls.size());
      for (size_t k = 0; k < nc; ++k)
        for (size_t i = 0; i < na; ++i)
          if (candidate[i * nc + k]) {
            b->overlap_balls.push_back(static_cast<uint16_t>(balls_of[c][k]));
            break;
          }
      rec.balls_b_end = static_cast<uint32_t>(b->overlap_balls.size());
      b->overlaps.push_back(rec);
      if (b->overlaps.size() > mb::kMaxOverlaps || b->overlap_balls.size() > mb::kMaxOverlapBalls)
        return *error = "metaballs: more bone pairs that can meet than the format holds (" +
                        std::to_string(b->overlaps.size()) + " records, " + std::to_string(b->overlap_balls.size()) +
                        " balls listed; coarser ball_spacing)",
               false;
    }
  return true;
}

}  // namespace sinew::metaballs_build
