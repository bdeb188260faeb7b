// TOML rig specs: a geometry source plus per-joint DOFs, limits and synergies.
//
//   [rig]
//   source = "builtin:arm"        # or a .gltf/.glb path, relative to the spec
//   skinning = "dqs"              # "lbs" or "dqs" (per-vertex method for all)
//
//   [[joint]]                     # replaces that joint's DOFs
//   name = "elbow"
//   kind = "rotation"             # or "translation"
//   dofs = [ { axis = [0, 0, 1], min = 0.0, max = 150.0 } ]   # degrees / units
//
//   [[synergy]]                   # target DOF += gain * source input
//   source = "elbow.0"            # "<joint>.<dof index>"
//   target = "wrist"
//   dof = 0
//   gain = 0.5
//
//   [motion.bvh_joints]           # motion files only (toml_motion.hpp)
//   elbow = "RightForeArm"
#pragma once

#include <string>

#include "host_tools/layers/rig_layers.hpp"
#include "rig_spec.hpp"

namespace sinew::rigc {

// Builds the RigSpec a TOML file describes. Errors name the file, the line and
// the key at fault.
bool load_toml_spec(const std::string& path, RigSpec* out, std::string* error);

// The same, with the spec's layer tables (toml_layers.hpp). Unknown top-level
// tables and unknown [rig] keys are refused.
bool load_toml_rig(const std::string& path, RigSpec* out, layers::LayerSpecs* layers, std::string* error);

}  // namespace sinew::rigc
