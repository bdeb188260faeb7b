#include "volume_loads.hpp"

#include <cmath>
#include <utility>

#include "host_tools/layers/common/dense_solve.hpp"
#include "host_tools/layers/common/rig_geometry.hpp"

namespace sinew::layers::barnet {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kForceLimit = 8;  // largest |f| tried, in units of the push (about the radius)

// sin and cos of |x| <= pi by their Taylor series: + - * / only, so the same
// bits on every platform (libm's may differ in the last place).
void sin_cos(double x, double* s, double* c) {
  double ts = x, tc = 1, ss = 0, sc = 0;
  for (int k = 0; k < 30; ++k) {
    ss += ts;
    sc += tc;
    ts *= -x * x / ((2.0 * k + 2) * (2.0 * k + 3));
    tc *= -x * x / ((2.0 * k + 1) * (2.0 * k + 2));
  }
  *s = ss, *c = sc;
}

struct Turn {
  double r[3][3];
  Vec3d centre;
};

Turn turn_about(const Vec3d& axis, const Vec3d& centre, double degrees) {
  double s = 0, c = 1;
  sin_cos(degrees * kPi / 180, &s, &c);
  const double x = axis[0], y = axis[1], z = axis[2], t = 1 - c;
  // Rodrigues: c I + s [a]x + (1 - c) a a^T.
  return {{{c + t * x * x, t * x * y - s * z, t * x * z + s * y},
           {t * x * y + s * z, c + t * y * y, t * y * z - s * x},
           {t * x * z - s * y, t * y * z + s * x, c + t * z * z}},
          centre};
}

Vec3d rotate(const Turn& turn, const Vec3d& v) {
  Vec3d out{0, 0, 0};
  for (size_t i = 0; i < 3; ++i) out[i] = turn.r[i][0] * v[0] + turn.r[i][1] * v[1] + turn.r[i][2] * v[2];
  return out;
}

// The net at one angle: every node's skinned position, and eq. (4)'s free
// nodes as x_a + f x_b for a push scaled by f.
struct NetAtAngle {
  std::vector<Vec3d> skinned;
  std::vector<Vec3d> base, per_push;  // per free node
};

class NetModel {
 public:
  NetModel(const rigc::RigSpec& rig, const RingLoadSchedule& r, const NetSpec& net) : rig_(rig), r_(r), net_(net) {
    slot_.assign(net.nodes.size(), -1);
    for (size_t i = 0; i < net.nodes.size(); ++i)
      if (!net.nodes[i].fixed) {
        slot_[i] = static_cast<int>(free_.size());
        free_.push_back(static_cast<uint32_t>(i));
      }
    const size_t n = free_.size();
    d_.assign(n * n, 0);
    rest_load_.assign(n, {0, 0, 0});
    for (const BarSpec& b : net.bars) {
      const int sa = slot_[b.a], sb = slot_[b.b];
      for (size_t c = 0; c < 3; ++c) {
        const double d = net.nodes[b.a].rest[c] - net.nodes[b.b].rest[c];
        if (sa >= 0) rest_load_[static_cast<size_t>(sa)][c] += b.q * d;
        if (sb >= 0) rest_load_[static_cast<size_t>(sb)][c] -= b.q * d;
      }
      if (sa >= 0) d_[static_cast<size_t>(sa) * n + static_cast<size_t>(sa)] += b.q;
      if (sb >= 0) d_[static_cast<size_t>(sb) * n + static_cast<size_t>(sb)] += b.q;
      if (sa >= 0 && sb >= 0) {
        d_[static_cast<size_t>(sa) * n + static_cast<size_t>(sb)] -= b.q;
        d_[static_cast<size_t>(sb) * n + static_cast<size_t>(sa)] -= b.q;
      }
    }
  }

  size_t free_count() const { return free_.size(); }

  NetAtAngle at(double degrees) const {
    const Turn turn = turn_about(r_.axis, r_.centre, degrees);
    const auto moves = [&](int palette) {
      return is_ancestor_or_self(rig_, r_.joint, rig_.palette[static_cast<size_t>(palette)].joint);
    };
    const auto place = [&](int palette, const Vec3d& p) {
      if (!moves(palette)) return p;
      const Vec3d q = rotate(turn, Vec3d{p[0] - turn.centre[0], p[1] - turn.centre[1], p[2] - turn.centre[2]});
      return Vec3d{q[0] + turn.centre[0], q[1] + turn.centre[1], q[2] + turn.centre[2]};
    };
    NetAtAngle out;
    out.skinned.assign(net_.nodes.size(), {0, 0, 0});
    for (size_t i = 0; i < net_.nodes.size(); ++i)
      for (const rigc::Influence& inf : net_.nodes[i].influences) {
        const Vec3d p = place(inf.palette, net_.nodes[i].rest);
        for (size_t c = 0; c < 3; ++c) out.skinned[i][c] += inf.weight * p[c];
      }
    // The rest loads turned by each node's blended bones at their bind-pose
    // magnitude (barnet_step.cpp), the push carried by the carrier's bone.
    const size_t n = free_.size();
    std::vector<double> rhs_a[3], rhs_b[3];
    for (size_t c = 0; c < 3; ++c) rhs_a[c].assign(n, 0), rhs_b[c].assign(n, 0);
    for (size_t k = 0; k < n; ++k) {
      const Vec3d p0 = rest_load_[k];
      Vec3d v{0, 0, 0};
      for (const rigc::Influence& inf : net_.nodes[free_[k]].influences) {
        const Vec3d t = moves(inf.palette) ? rotate(turn, p0) : p0;
        for (size_t c = 0; c < 3; ++c) v[c] += inf.weight * t[c];
      }
      const double size = std::sqrt(p0[0] * p0[0] + p0[1] * p0[1] + p0[2] * p0[2]);
      const double turned = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      for (size_t c = 0; c < 3; ++c) rhs_a[c][k] = turned > 0 ? v[c] / turned * size : 0;
    }
    const bool carrier_moves = is_ancestor_or_self(rig_, r_.joint, r_.carrier);
    for (size_t j = 0; j < r_.nodes.size(); ++j) {
      const Vec3d push = carrier_moves ? rotate(turn, r_.push[j]) : r_.push[j];
      for (size_t c = 0; c < 3; ++c) rhs_b[c][static_cast<size_t>(slot_[r_.nodes[j]])] += push[c];
    }
    // - D_f x_f: + q x_f on the free end of each bar to a fixed node.
    for (const BarSpec& b : net_.bars) {
      const int sa = slot_[b.a], sb = slot_[b.b];
      for (size_t c = 0; c < 3; ++c) {
        if (sa >= 0 && sb < 0) rhs_a[c][static_cast<size_t>(sa)] += b.q * out.skinned[b.b][c];
        if (sb >= 0 && sa < 0) rhs_a[c][static_cast<size_t>(sb)] += b.q * out.skinned[b.a][c];
      }
    }
    out.base.assign(n, {0, 0, 0});
    out.per_push.assign(n, {0, 0, 0});
    for (size_t c = 0; c < 3; ++c) {
      const std::vector<double> xa = solve_dense(d_, rhs_a[c]), xb = solve_dense(d_, rhs_b[c]);
      for (size_t k = 0; k < n; ++k) out.base[k][c] = xa[k], out.per_push[k][c] = xb[k];
    }
    return out;
  }

  // Signed volume of the tube with the push scaled by f, closed by a fan at
  // each end ring's centroid (signed, so a tube pushed inside out does not
  // count as full).
  double volume(const NetAtAngle& a, double f) const {
    std::vector<Vec3d> x = a.skinned;
    for (size_t k = 0; k < free_.size(); ++k)
      for (size_t c = 0; c < 3; ++c) x[free_[k]][c] = a.base[k][c] + f * a.per_push[k][c];
    return enclosed(x);
  }
  double rest_volume() const {
    std::vector<Vec3d> x;
    for (const NodeSpec& n : net_.nodes) x.push_back(n.rest);
    return enclosed(x);
  }

 private:
  double enclosed(const std::vector<Vec3d>& x) const {
    const auto tet = [](const Vec3d& a, const Vec3d& b, const Vec3d& c) {
      return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
              a[2] * (b[0] * c[1] - b[1] * c[0])) /
             6;
    };
    double v = 0;
    for (const auto& t : net_.triangles) v += tet(x[t[0]], x[t[1]], x[t[2]]);
    const uint32_t seg = static_cast<uint32_t>(r_.segments);
    for (const int ring : {0, r_.rings - 1}) {
      const uint32_t first = static_cast<uint32_t>(ring) * seg;
      Vec3d centre{0, 0, 0};
      for (uint32_t k = 0; k < seg; ++k)
        for (size_t c = 0; c < 3; ++c) centre[c] += x[first + k][c] / seg;
      // The mesh's outward side: rings advance along the axis, k turns
      // counter-clockwise (add_tube_mesh), so the first ring's cap faces
      // back and the last one's forward.
      for (uint32_t k = 0; k < seg; ++k) {
        const Vec3d& a = x[first + k];
        const Vec3d& b = x[first + (k + 1) % seg];
        v += ring == 0 ? tet(centre, b, a) : tet(centre, a, b);
      }
    }
    return v;
  }

  const rigc::RigSpec& rig_;
  const RingLoadSchedule& r_;
  const NetSpec& net_;
  std::vector<int> slot_;
  std::vector<uint32_t> free_;
  std::vector<double> d_;
  std::vector<Vec3d> rest_load_;
};

}  // namespace

bool volume_keeping_schedule(const rigc::RigSpec& rig, const RingLoadSchedule& r, const NetSpec& net,
                             VolumeSchedule* out, std::string* error) {
  if (r.steps < 1 || r.steps > 64) return *error = "volume schedule: steps must be 1..64", false;
  if (r.flex_hi == 0 || r.flex_hi < -180 || r.flex_hi > 180)
    return *error = "volume schedule: the flexion must end within +-180 degrees, not at 0", false;
  if (r.nodes.size() != r.push.size() || r.nodes.empty())
    return *error = "volume schedule: one push per loaded node, at least one", false;
  if (r.rings < 2 || r.segments < 3 || net.nodes.size() != static_cast<size_t>(r.rings * r.segments))
    return *error = "volume schedule: the net is not a tube of rings x segments nodes", false;
  for (uint32_t node : r.nodes)
    if (node >= net.nodes.size() || net.nodes[node].fixed)
      return *error = "volume schedule: a loaded node is not a free node of the net", false;
  const NetModel model(rig, r, net);
  const double rest = model.rest_volume();
  out->angle = {0};
  out->f = {0};
  out->short_steps = 0;
  for (int k = 1; k <= r.steps; ++k) {
    const double angle = r.flex_hi * k / r.steps;
    const NetAtAngle a = model.at(angle);
    // The volume is not monotone in f over a wide range (a tube pushed far
    // in either direction swells), so bracket the root nearest f = 0:
    // step away from 0 in the direction that corrects the volume, doubling,
    // until the sign of the error changes.
    const double at_zero = model.volume(a, 0) - rest;
    const double direction = at_zero < 0 ? 1 : -1;
    // A bend so deep that no push within the limit restores the volume (the
    // tube folded onto itself) keeps the previous step's push rather than
    // inflating the ring without end, and is counted in `short_steps`.
    double near = 0, far = 0;
    bool bracketed = at_zero == 0;
    for (double step = 1.0 / 256; !bracketed && step <= kForceLimit; step *= 2) {
      far = direction * step;
      if ((model.volume(a, far) - rest < 0) != (at_zero < 0))
        bracketed = true;
      else
        near = far;
    }
    if (!bracketed) {
      ++out->short_steps;
      out->angle.push_back(angle);
      out->f.push_back(out->f.back());
      continue;
    }
    for (int it = 0; it < 80 && at_zero != 0; ++it) {
      const double mid = (near + far) / 2;
      if ((model.volume(a, mid) - rest < 0) == (at_zero < 0))
        near = mid;
      else
        far = mid;
    }
    const double f = at_zero == 0 ? 0 : (near + far) / 2;
    out->angle.push_back(angle);
    out->f.push_back(f);
  }
  return true;
}

bool add_volume_keeping_loads(const rigc::RigSpec& rig, const RingLoadSchedule& r, NetSpec* net, std::string* error) {
  VolumeSchedule s;
  if (!volume_keeping_schedule(rig, r, *net, &s, error)) return false;
  net->volume_steps = static_cast<int>(s.angle.size()) - 1;
  net->volume_short_steps = s.short_steps;
  // Piecewise linear in the angle: step k's loads ramp in over
  // [angle_{k-1}, angle_k] and add f_k - f_{k-1} (activation is 0 below the
  // step and 1 above it, barnet_model.hpp).
  for (size_t k = 1; k < s.angle.size(); ++k) {
    const double df = s.f[k] - s.f[k - 1];
    for (size_t j = 0; j < r.nodes.size(); ++j) {
      LoadSpec l;
      l.node = r.nodes[j];
      l.joint = r.carrier;
      l.input = r.input;
      l.angle_lo = s.angle[k - 1];
      l.angle_hi = s.angle[k];
      l.force = {r.push[j][0] * df, r.push[j][1] * df, r.push[j][2] * df};
      net->loads.push_back(l);
    }
  }
  return true;
}

}  // namespace sinew::layers::barnet
