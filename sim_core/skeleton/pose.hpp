// Skeleton jobs (ozz-animation style: spans in, spans out, no allocation):
//   dofs_to_locals:  commanded DOF inputs -> synergies -> clamped DOF values
//                    -> local joint transforms
//   locals_to_model: local transforms -> model-space transforms (parents first)
//   skinning_palette: model transforms x inverse binds -> skinning matrices
//                    (and unit dual quaternions for DQS vertices)
#pragma once

#include <cstdint>
#include <span>

#include "sim_core/fixed/dual_quat.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::skeleton {

// A joint's local transform, T * R * S.
struct LocalPose {
  fx::Vec3 translation;  // Len, rig units
  fx::Quat rotation;     // Q2.30, unit
  fx::Vec3 scale;        // Q8.24
};

enum JointFlag : uint8_t {
  kJointClamped = 1u << 0,  // a DOF hit its limit this step
};

void rest_locals(const rig::Rig& rig, std::span<LocalPose> locals);

// inputs: one value per rig input: a signed binary angle (int32 view of an
// Angle) for rotational DOFs, a Len for translational ones. Each joint DOF
// takes its own input plus sum(gain * source input) of the synergies that
// target it (anatomically-based §3); a shared synergy (SynergyMode::kShare,
// major-2 blobs) also takes that same amount off its source's own DOF, so a
// chain's DOF values sum exactly to the command. Then each value is clamped
// to [dof_min, dof_max]
// (LEMAN §6.8). The rotation is rest_rotation * R(axis0, a0) * R(axis1, a1)
// * R(axis2, a2). Returns the number of DOFs clamped; sets joint_flags.
// measured: empty, or one byte per rig input, nonzero when a source measures
// that DOF (a glove's DIP sensor): a synergy never adds to a measured DOF, so
// the DOF is the measured angle, and a shared synergy whose target is
// measured moves nothing off its source either. The coupling is a model of
// what is not measured, not a correction on top of a measurement.
// Spans: inputs >= rig.input_count, locals and joint_flags >= joint count.
uint32_t dofs_to_locals(const rig::Rig& rig, std::span<const int32_t> inputs, std::span<const uint8_t> measured,
                        std::span<LocalPose> locals, std::span<uint8_t> joint_flags);

void locals_to_model(const rig::Rig& rig, std::span<const LocalPose> locals, std::span<fx::Mat34> model);

// skin: one matrix per palette entry. dual: empty, or one per palette entry
// (filled only when the rig has DQS vertices).
void skinning_palette(const rig::Rig& rig, std::span<const fx::Mat34> model, std::span<fx::Mat34> skin,
                      std::span<fx::DualQuat> dual);

// Rotation quaternion of a rigid linear part (Q8.24), Shepperd's method.
fx::Quat quat_from_linear(const fx::Lin m[3][3]);

}  // namespace sinew::skeleton
