// Stages 1-2: bone deformations, normal-ball kinematics (eq. 2) and bulging.
#include "kernels.hpp"
#include "rotation.hpp"
#include "sim_core/skeleton/pose.hpp"

namespace sinew::metaballs::detail {
namespace {

// The linear part of a bone deformation with entries clamped to [-1, 1]
// (Q8.24). A rigid skeleton gives a rotation, whose entries already lie there
// (to rounding); the clamp keeps the rotation extraction and the trace below
// overflow-free for any caller-provided transform.
struct Linear {
  fx::Lin m[3][3];
};

Linear clamped_linear(const fx::Mat34& t) {
  Linear l;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) l.m[i][k] = static_cast<fx::Lin>(fx::clamp_i64(t.m[i][k], -fx::kLinOne, fx::kLinOne));
  return l;
}

// (1 - cos theta) / 2 in Q2.30 for the angle theta between the rotations of
// two bone deformations: cos theta = (tr(R_a R_b^T) - 1) / 2, and
// tr(R_a R_b^T) is the entrywise dot product of the two linear parts (Q48).
fx::Unit flexion(const fx::Mat34& a, const fx::Mat34& b) {
  const Linear la = clamped_linear(a), lb = clamped_linear(b);
  int64_t trace = 0;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) trace += int64_t{la.m[i][k]} * lb.m[i][k];  // 9 products <= 2^48 each
  const int64_t f48 = fx::clamp_i64((3 * (int64_t{1} << 48) - trace) / 4, 0, int64_t{1} << 48);
  return static_cast<fx::Unit>(fx::round_shift(f48, 18));
}

}  // namespace

void compute_bones(const MetaballModel& m, std::span<const fx::Mat34> joint_model, MetaballState* s) {
  for (uint32_t j = 0; j < m.joint_count; ++j) {
    s->bone[j] = fx::mul(joint_model[j], m.inverse_bind[j]);
    s->bone_rotation[j] = skeleton::quat_from_linear(clamped_linear(s->bone[j]).m);
  }
}

namespace {

// Eq. (2) for a ball of two bones, as one rigid motion: the dual-quaternion
// blend of the bones' deformations by the ball's weights (docs/metaballs.md,
// "Balls of two bones"). Its rotation is the normalised blend of the bones'
// rotations (the paper's Slerp, on the same arc), and a ball at the joint the
// two bones share turns about it, on the arc: the linear blend of eq. (2) as
// written moves the ball along the chord, shortening the tube at a bent
// joint (0.71 of the bone spacing at 90 degrees and equal weights).
fx::DualQuat blended_bones(const MetaballState& s, const uint16_t joints[2], const fx::Unit weights[2]) {
  DualQuatBlend blend;
  for (int k = 0; k < 2; ++k) {
    const fx::Mat34& t = s.bone[joints[k]];
    blend.add(fx::dual_quat_from_rt(s.bone_rotation[joints[k]], {t.t[0], t.t[1], t.t[2]}), weights[k]);
  }
  return blend.unit();
}

}  // namespace

void compute_balls(const MetaballModel& m, MetaballState* s) {
  for (uint32_t b = 0; b < m.ball_count(); ++b) {
    const uint16_t* joints = &m.ball_joint[size_t{b} * kBallInfluences];
    const fx::Unit* weights = &m.ball_weight[size_t{b} * kBallInfluences];
    static_assert(kBallInfluences == 2);
    if (weights[0] != 0 && weights[1] != 0) {
      const fx::DualQuat dq = blended_bones(*s, joints, weights);
      s->ball_target[b] = fx::transform_point(dq, m.ball_rest[b]);
      s->ball_quat[b] = dq.real;
      s->ball_rotation[b] = fx::rot3_of_unit(dq.real);
      s->ball_scale[b] = fx::kUnitOne;
      continue;
    }
    // One bone: eq. (2) is that bone's deformation of the rest centre.
    const uint32_t k = weights[0] != 0 ? 0 : 1;
    s->ball_target[b] = fx::transform_point(s->bone[joints[k]], m.ball_rest[b]);
    s->ball_quat[b] = s->bone_rotation[joints[k]];
    s->ball_rotation[b] = fx::rot3_of_unit(s->ball_quat[b]);
    s->ball_scale[b] = fx::kUnitOne;
  }
  if (!s->features.bulge) return;
  for (const BulgeRecord& r : m.bulges) {
    // Muscle bulging: r = r0 (1 + gain (1 - cos theta) / 2), gain < 1.
    const fx::Unit f = flexion(s->bone[r.bone_a], s->bone[r.bone_b]);
    s->ball_scale[r.ball] = fx::kUnitOne + fx::mul_unit(r.gain, f);
  }
}

}  // namespace sinew::metaballs::detail
