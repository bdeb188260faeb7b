// Built-in procedural rigs, so the default job needs no file:
//   arm:  shoulder (3 DOF), elbow (1), forearm twist (1), wrist (2);
//         a skin tube of ~4k vertices along +x, lengths in metres.
//   hand: wrist (2 DOF) + 5 fingers x 3 joints (MCP 2 DOF, PIP 1, DIP 1, with
//         the DIP coupled to the PIP by a 2/3 synergy); ~4k vertices.
// Geometry uses sim_core's integer trig and exact IEEE operations only, so the
// compiled blob is bit-identical on every platform.
#pragma once

#include <string>
#include <vector>

#include "rig_spec.hpp"

namespace sinew::rigc {

enum class SkinChoice { kLinear, kDualQuaternion };

RigSpec builtin_arm(SkinChoice method = SkinChoice::kDualQuaternion);
RigSpec builtin_hand(SkinChoice method = SkinChoice::kDualQuaternion);

// "arm" or "hand"; false for an unknown name.
bool builtin_rig(const std::string& name, SkinChoice method, RigSpec* out);

// One name per input, in input order: "<joint>.<dof index>".
std::vector<std::string> input_names(const RigSpec& spec);

// Index of a named joint, or -1.
int joint_index(const RigSpec& spec, const std::string& name);

// Rings of the arm's skin tube: ring r holds vertices [r * segments, (r+1) * segments).
inline constexpr int kArmRingSegments = 32;

}  // namespace sinew::rigc
