#include "pose.hpp"

#include <algorithm>

#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/sqrt.hpp"

namespace sinew::skeleton {

void rest_locals(const rig::Rig& rig, std::span<LocalPose> locals) {
  for (uint32_t j = 0; j < rig.joint_count(); ++j) {
    const rig::JointRecord& r = rig.joints[j];
    locals[j] = {{r.rest_translation[0], r.rest_translation[1], r.rest_translation[2]},
                 {r.rest_rotation[0], r.rest_rotation[1], r.rest_rotation[2], r.rest_rotation[3]},
                 {r.rest_scale[0], r.rest_scale[1], r.rest_scale[2]}};
  }
}

uint32_t dofs_to_locals(const rig::Rig& rig, std::span<const int32_t> inputs, std::span<const uint8_t> measured,
                        std::span<LocalPose> locals, std::span<uint8_t> joint_flags) {
  const auto is_measured = [&](const rig::SynergyRecord& s) {
    const uint32_t target = rig.joints[s.target_joint].first_input + uint32_t{s.target_dof};
    return target < measured.size() && measured[target] != 0;
  };
  rest_locals(rig, locals);
  uint32_t clamped = 0;
  for (uint32_t j = 0; j < rig.joint_count(); ++j) {
    const rig::JointRecord& r = rig.joints[j];
    joint_flags[j] = 0;
    if (r.dof_count == 0) continue;
    int64_t value[3] = {0, 0, 0};
    for (int d = 0; d < r.dof_count; ++d) value[d] = inputs[r.first_input + static_cast<uint32_t>(d)];
    // Synergies spread a commanded value over other joints' DOFs. The list is
    // short and bounded (kMaxSynergies); a linear scan keeps order deterministic.
    // A shared synergy (anatomically-based §3: "a 12 degree rotation of the
    // thoracic region is ... one degree at each thoracic vertebra") moves its
    // share from the source's own DOF to the target, the same rounded integer
    // on both sides, so the chain's values sum exactly to the command.
    for (const rig::SynergyRecord& s : rig.synergies) {
      const bool share = rig.synergy_shares && s.mode == static_cast<uint8_t>(rig::SynergyMode::kShare);
      const bool targets_this = s.target_joint == j;
      const uint32_t source = s.source_input;
      const bool sources_this = share && source >= r.first_input && source < r.first_input + uint32_t{r.dof_count};
      if (!targets_this && !sources_this) continue;
      if (is_measured(s)) continue;  // the measured angle stands alone
      const int64_t amount = fx::round_shift(int64_t{inputs[s.source_input]} * s.gain, fx::kUnitFracBits);
      if (targets_this) value[s.target_dof] += amount;
      if (sources_this) value[source - r.first_input] -= amount;
    }
    fx::Quat dof_rotation = fx::quat_identity();
    for (int d = 0; d < r.dof_count; ++d) {
      int64_t v = value[d];
      if (v < r.dof_min[d] || v > r.dof_max[d]) {
        v = fx::clamp_i64(v, r.dof_min[d], r.dof_max[d]);
        joint_flags[j] |= kJointClamped;
        ++clamped;
      }
      const fx::Vec3 axis{r.dof_axis[d][0], r.dof_axis[d][1], r.dof_axis[d][2]};
      if (r.dof_kind == static_cast<uint8_t>(rig::DofKind::kRotation)) {
        const fx::Angle a = static_cast<fx::Angle>(static_cast<uint32_t>(static_cast<int32_t>(v)));
        dof_rotation = fx::mul(dof_rotation, fx::quat_from_axis_angle(axis, a));
      } else {
        const fx::Vec3 offset{fx::mul_by_unit(static_cast<int32_t>(v), axis.x),
                              fx::mul_by_unit(static_cast<int32_t>(v), axis.y),
                              fx::mul_by_unit(static_cast<int32_t>(v), axis.z)};
        locals[j].translation = fx::add(locals[j].translation, offset);
      }
    }
    if (r.dof_kind == static_cast<uint8_t>(rig::DofKind::kRotation)) {
      locals[j].rotation = fx::mul(locals[j].rotation, dof_rotation);
      fx::normalize(&locals[j].rotation);
    }
  }
  return clamped;
}

void locals_to_model(const rig::Rig& rig, std::span<const LocalPose> locals, std::span<fx::Mat34> model) {
  for (uint32_t j = 0; j < rig.joint_count(); ++j) {
    const LocalPose& l = locals[j];
    const fx::Mat34 local = fx::mat34_from_trs(l.translation, l.rotation, l.scale);
    const int32_t parent = rig.joints[j].parent;
    // Parents precede children (validated by the loader), so model[parent] is ready.
    model[j] = parent < 0 ? local : fx::mul(model[static_cast<uint32_t>(parent)], local);
  }
}

fx::Quat quat_from_linear(const fx::Lin m[3][3]) {
  // Work in Q30 (entries of a rotation are within [-1, 1]). A linear part
  // with scale (any rest_scale the format accepts) may hold entries up to
  // +-128: they are clamped to +-1.5 first, which leaves every rotation and
  // mild scale unchanged and keeps |numerator x 2^30| <= 3 x 2^60, inside
  // div_round's |n| < 2^62 (no overflow for any input).
  const int64_t limit = (int64_t{3} << 30) / 2;
  int64_t r[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) r[i][k] = std::clamp<int64_t>(int64_t{m[i][k]} * 64, -limit, limit);
  const int64_t one = int64_t{1} << 30;
  const int64_t trace = r[0][0] + r[1][1] + r[2][2];
  // Shepperd: take the largest of 4w^2, 4x^2, 4y^2, 4z^2 for a stable divisor.
  const int64_t cand[4] = {one + trace, one + r[0][0] - r[1][1] - r[2][2], one - r[0][0] + r[1][1] - r[2][2],
                           one - r[0][0] - r[1][1] + r[2][2]};
  int best = 0;
  for (int i = 1; i < 4; ++i)
    if (cand[i] > cand[best]) best = i;
  // s = 2 * sqrt(cand) in Q30: sqrt of a Q30 value is isqrt(v << 30) in Q30.
  const int64_t c = cand[best] > 0 ? cand[best] : 1;
  const int64_t s = 2 * static_cast<int64_t>(fx::isqrt_fast(static_cast<uint64_t>(c) << 30));
  const auto q_of = [&](int64_t numerator) { return fx::sat_i32(fx::div_round(numerator * one, s)); };
  const fx::Unit quarter_s = fx::sat_i32(s / 4);
  fx::Quat q{};
  switch (best) {
    case 0:
      q = {quarter_s, q_of(r[2][1] - r[1][2]), q_of(r[0][2] - r[2][0]), q_of(r[1][0] - r[0][1])};
      break;
    case 1:
      q = {q_of(r[2][1] - r[1][2]), quarter_s, q_of(r[0][1] + r[1][0]), q_of(r[0][2] + r[2][0])};
      break;
    case 2:
      q = {q_of(r[0][2] - r[2][0]), q_of(r[0][1] + r[1][0]), quarter_s, q_of(r[1][2] + r[2][1])};
      break;
    default:
      q = {q_of(r[1][0] - r[0][1]), q_of(r[0][2] + r[2][0]), q_of(r[1][2] + r[2][1]), quarter_s};
      break;
  }
  fx::normalize(&q);
  return q;
}

void skinning_palette(const rig::Rig& rig, std::span<const fx::Mat34> model, std::span<fx::Mat34> skin,
                      std::span<fx::DualQuat> dual) {
  for (uint32_t p = 0; p < rig.palette.size(); ++p) {
    const rig::PaletteRecord& entry = rig.palette[p];
    skin[p] = fx::mul(model[entry.joint], entry.inverse_bind);
    if (!dual.empty() && rig.any_dual_quaternion) {
      const fx::Quat q = quat_from_linear(skin[p].m);
      dual[p] = fx::dual_quat_from_rt(q, {skin[p].t[0], skin[p].t[1], skin[p].t[2]});
    }
  }
}

}  // namespace sinew::skeleton
