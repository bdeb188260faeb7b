// The primary deformation (eq. 1, 2, 4, 5 with bulging, each vertex one rigid
// motion as deform.cpp computes it, balls of two bones and the vertices of
// balls that turn differently by dual-quaternion blending; PBD, smoothing and overlap off) against a
// double-precision evaluation of the same equations from the same model and
// joint transforms. Native only.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>

#include "arm_scene.hpp"

namespace {

namespace mb = sinew::metaballs;
using Q = std::array<double, 4>;  // w, x, y, z
using V = std::array<double, 3>;

struct Affine {
  double m[3][3];
  double t[3];  // rig units
};

Affine to_double(const sinew::fx::Mat34& a) {
  Affine r{};
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) r.m[i][k] = std::ldexp(a.m[i][k], -24);
    r.t[i] = std::ldexp(a.t[i], -20);
  }
  return r;
}

Affine mul(const Affine& a, const Affine& b) {
  Affine r{};
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) r.m[i][k] = a.m[i][0] * b.m[0][k] + a.m[i][1] * b.m[1][k] + a.m[i][2] * b.m[2][k];
    r.t[i] = a.m[i][0] * b.t[0] + a.m[i][1] * b.t[1] + a.m[i][2] * b.t[2] + a.t[i];
  }
  return r;
}

V lin_apply(const double m[3][3], const V& p) {
  return {m[0][0] * p[0] + m[0][1] * p[1] + m[0][2] * p[2], m[1][0] * p[0] + m[1][1] * p[1] + m[1][2] * p[2],
          m[2][0] * p[0] + m[2][1] * p[1] + m[2][2] * p[2]};
}

Q normalized(Q q) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& c : q) c /= n;
  return q;
}

Q quat_of(const double m[3][3]) {  // Shepperd
  const double tr = m[0][0] + m[1][1] + m[2][2];
  if (tr >= m[0][0] && tr >= m[1][1] && tr >= m[2][2]) {
    const double s = 2 * std::sqrt(1 + tr);
    return normalized({s / 4, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s});
  }
  if (m[0][0] >= m[1][1] && m[0][0] >= m[2][2]) {
    const double s = 2 * std::sqrt(1 + m[0][0] - m[1][1] - m[2][2]);
    return normalized({(m[2][1] - m[1][2]) / s, s / 4, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s});
  }
  if (m[1][1] >= m[2][2]) {
    const double s = 2 * std::sqrt(1 - m[0][0] + m[1][1] - m[2][2]);
    return normalized({(m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s, s / 4, (m[1][2] + m[2][1]) / s});
  }
  const double s = 2 * std::sqrt(1 - m[0][0] - m[1][1] + m[2][2]);
  return normalized({(m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, s / 4});
}

Q nlerp(const Q& a, Q b, double t) {
  if (a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] < 0)
    for (double& c : b) c = -c;
  return normalized(
      {(1 - t) * a[0] + t * b[0], (1 - t) * a[1] + t * b[1], (1 - t) * a[2] + t * b[2], (1 - t) * a[3] + t * b[3]});
}

void rot_of(const Q& q, double r[3][3]) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double m[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) r[i][k] = m[i][k];
}

V v3(sinew::fx::Vec3 v) { return {std::ldexp(v.x, -20), std::ldexp(v.y, -20), std::ldexp(v.z, -20)}; }

Q qmul(const Q& a, const Q& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3], a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1], a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

// A rigid motion x -> R x + t as a dual quaternion (Kavan et al.), and the
// blend of several by weights (each on the first's hemisphere, normalised):
// dual-quaternion blending, written from its definition.
struct Dq {
  Q real{0, 0, 0, 0}, dual{0, 0, 0, 0};
};

Dq dq_of(const Q& q, const V& t) {
  const Q d = qmul({0, t[0], t[1], t[2]}, q);
  return {q, {d[0] / 2, d[1] / 2, d[2] / 2, d[3] / 2}};
}

struct DqBlend {
  Dq sum;
  Q pivot{0, 0, 0, 0};
  bool any = false;
  void add(const Dq& d, double w) {
    if (!any) pivot = d.real, any = true;
    const double dot = pivot[0] * d.real[0] + pivot[1] * d.real[1] + pivot[2] * d.real[2] + pivot[3] * d.real[3];
    const double sw = dot < 0 ? -w : w;
    for (int c = 0; c < 4; ++c) {
      sum.real[c] += sw * d.real[c];
      sum.dual[c] += sw * d.dual[c];
    }
  }
  // The blend's rotation and its action on a point.
  Q rotation() const { return normalized(sum.real); }
  V apply(const V& p) const {
    const double n = std::sqrt(sum.real[0] * sum.real[0] + sum.real[1] * sum.real[1] + sum.real[2] * sum.real[2] +
                               sum.real[3] * sum.real[3]);
    const Q r = rotation();
    Q d{sum.dual[0] / n, sum.dual[1] / n, sum.dual[2] / n, sum.dual[3] / n};
    const double k = r[0] * d[0] + r[1] * d[1] + r[2] * d[2] + r[3] * d[3];
    for (int c = 0; c < 4; ++c) d[c] -= k * r[c];
    const Q t = qmul(d, {r[0], -r[1], -r[2], -r[3]});  // t / 2
    double m[3][3];
    rot_of(r, m);
    const V rp = lin_apply(m, p);
    return {rp[0] + 2 * t[1], rp[1] + 2 * t[2], rp[2] + 2 * t[3]};
  }
};

}  // namespace

TEST(MetaballsOracle, PrimaryDeformationMatchesDoublePrecision) {
  sinew::metaballs_build::Options o = sinew::test::arm_options();
  o.bulge.push_back({"shoulder", 0.3, 0.7, "shoulder", "elbow", 0.3});
  sinew::test::ArmScene s(sinew::rigc::SkinChoice::kDualQuaternion, o);
  ASSERT_TRUE(s.ok()) << s.error();
  s.state().features.pbd = s.state().features.smoothing = s.state().features.overlap = false;
  const mb::MetaballModel& m = s.model();
  const double lsb = std::ldexp(1.0, s.build().length_exponent - 20);  // metres per Len step
  const double poses[][3] = {{0, 0, 0}, {30, 90, 180}, {-45, 150, -90}, {80, 45, 37}, {120, 10, 100}};
  double worst = 0;
  for (const auto& p : poses) {
    ASSERT_TRUE(s.pose(p[0], p[1], p[2]));
    std::vector<Affine> bone(m.joint_count);
    std::vector<Q> q(m.joint_count);
    for (uint32_t j = 0; j < m.joint_count; ++j) {
      bone[j] = mul(to_double(s.engine().model[j]), to_double(m.inverse_bind[j]));
      q[j] = quat_of(bone[j].m);
    }
    const uint32_t nb = m.ball_count();
    std::vector<V> centre(nb);
    std::vector<Q> ball_q(nb);
    std::vector<double> scale(nb, 1.0);
    for (uint32_t b = 0; b < nb; ++b) {
      const uint16_t j0 = m.ball_joint[2 * b], j1 = m.ball_joint[2 * b + 1];
      const double w0 = std::ldexp(m.ball_weight[2 * b], -30), w1 = std::ldexp(m.ball_weight[2 * b + 1], -30);
      const V c = v3(m.ball_rest[b]);
      // Eq. (2) as one rigid motion: the bones' deformations blended as
      // dual quaternions (a ball of one bone: that bone's).
      DqBlend blend;
      blend.add(dq_of(q[j0], {bone[j0].t[0], bone[j0].t[1], bone[j0].t[2]}), w0);
      if (w1 != 0) blend.add(dq_of(q[j1], {bone[j1].t[0], bone[j1].t[1], bone[j1].t[2]}), w1);
      centre[b] = blend.apply(c);
      ball_q[b] = blend.rotation();
    }
    for (const auto& bu : m.bulges) {
      double tr = 0;
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) tr += bone[bu.bone_a].m[i][k] * bone[bu.bone_b].m[i][k];
      scale[bu.ball] = 1 + std::ldexp(bu.gain, -30) * std::clamp((3 - tr) / 4, 0.0, 1.0);
    }
    // Eq. (4) with the balls' rotations blended before they act: the blended
    // centre and rest displacement, turned by the balls' rotations blended by
    // the same weights (each on the first's hemisphere, normalised).
    struct Frame {
      V centre{0, 0, 0}, disp{0, 0, 0}, rest{0, 0, 0};
      Q q{0, 0, 0, 0};
    };
    std::vector<Frame> frame(m.vertex_count);
    std::vector<V> out(m.vertex_count);
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
      // Eq. (4) as one rigid motion: the balls' frames
      // F_b(x) = c_b + R_b (x - c0_b) blended as dual quaternions, applied to
      // the blended rest centre, plus the blended (bulge-scaled)
      // displacement turned by the blend's rotation.
      Frame& f = frame[v];
      DqBlend blend;
      for (uint32_t k = 0; k < mb::kVertexBalls; ++k) {
        const size_t i = size_t{v} * mb::kVertexBalls + k;
        const double w = std::ldexp(m.vertex_weight[i], -30);
        if (w == 0) continue;
        const uint16_t b = m.vertex_ball[i];
        double rb[3][3];
        rot_of(ball_q[b], rb);
        const V c0 = v3(m.ball_rest[b]), rc0 = lin_apply(rb, c0);
        blend.add(dq_of(ball_q[b], {centre[b][0] - rc0[0], centre[b][1] - rc0[1], centre[b][2] - rc0[2]}), w);
        const V d = v3(m.vertex_disp[i]);
        for (int a = 0; a < 3; ++a) {
          f.rest[a] += w * c0[a];
          f.disp[a] += w * scale[b] * d[a];
        }
      }
      f.q = blend.rotation();
      f.centre = blend.apply(f.rest);
      double r[3][3];
      rot_of(f.q, r);
      const V rd = lin_apply(r, f.disp);
      for (int a = 0; a < 3; ++a) out[v][a] = f.centre[a] + rd[a];
    }
    // Eq. (5) and eq. (1) as one rigid motion: centre and displacement
    // blended by w^alpha, the two rotations by nlerp.
    for (uint32_t i = 0; i < m.jv_count(); ++i) {
      const mb::JointBall& jb = m.joint_balls[m.jv_ball[i]];
      const uint32_t v = m.jv_vertex[i];
      const Q eta = nlerp(q[jb.bone_a], q[jb.bone_b], std::ldexp(m.jv_blend[i], -30));
      const double alpha = std::ldexp(m.jv_alpha[i], -30);
      double r[3][3];
      rot_of(nlerp(frame[v].q, eta, alpha), r);
      const V de = v3(m.jv_disp[i]);
      V d{};
      for (int a = 0; a < 3; ++a) d[a] = (1 - alpha) * frame[v].disp[a] + alpha * de[a];
      const V rd = lin_apply(r, d);
      for (int a = 0; a < 3; ++a)
        out[v][a] = (1 - alpha) * frame[v].centre[a] + alpha * std::ldexp(s.engine().model[jb.joint].t[a], -20) + rd[a];
    }
    double pose_worst = 0;
    for (uint32_t v = 0; v < m.vertex_count; ++v)
      for (int a = 0; a < 3; ++a)
        pose_worst = std::max(pose_worst, std::fabs(std::ldexp(s.output().position[a][v], -20) - out[v][a]));
    std::printf("oracle: shoulder %4.0f elbow %4.0f twist %4.0f deg: largest |fixed - double| %.2f LSB (%.2e m)\n",
                p[0], p[1], p[2], pose_worst * 1048576.0, pose_worst * 1048576.0 * lsb);
    worst = std::max(worst, pose_worst * 1048576.0);
  }
  // Bound: the 8 LSB of the nlerp frame (the five Len roundings of the
  // frame, the eq. (1) blend and R D, each within sqrt(3) / 2 LSB, and the
  // rotation's) plus, for each dual-quaternion motion (eq. 2's ball, then
  // eq. 4's frame), its translation 2 dual conj(real): a dual part off by at
  // most 2.5 LSB a component (the product's and the halving's roundings in
  // dual_quat_from_rt, the blend's, normalize_fast's and its projection's)
  // moves it by at most 2 x 2 x 2.5 = 10 LSB. 8 + 2 x 10 = 28.
  EXPECT_LT(worst, 28.0) << "LSB of Q12.20";
}
