// The daemon's rig: a built-in compiled in-process or a blob file from rigc,
// validated by sim_core's loader. Memory is sized once here.
#pragma once

#include <string>
#include <vector>

#include "sim_core/rig/rig.hpp"

namespace sinew::firmware {

// An input the daemon reads besides the rig's joint DOFs, for a layer: e.g.
// the force on the SPH elbow ("elbow.force", newtons in Q16.16). It is fed,
// health-checked, held and logged like a joint input, but the skeleton does
// not see it: the layer that declared it reads it.
struct ExternalInput {
  std::string name;
  int32_t min = 0, max = 0;  // accepted range before the range margin, engine units
  bool force = false;        // newtons Q16.16 (else the rig's length units)
};

struct LoadedRig {
  std::vector<uint64_t> blob;  // 8-byte aligned
  std::vector<uint64_t> arena;
  rig::Rig rig;
  // "<joint>.<dof>" for the rig's inputs 0 .. rig.input_count - 1, then the
  // external inputs' names.
  std::vector<std::string> input_names;
  std::vector<ExternalInput> external;  // inputs rig.input_count onwards

  uint32_t input_count() const { return static_cast<uint32_t>(input_names.size()); }
  // Appends an external input; returns its index.
  uint32_t add_external(ExternalInput input);
};

bool load_rig(const std::string& builtin, const std::string& blob_path, LoadedRig* out, std::string* error);

}  // namespace sinew::firmware
