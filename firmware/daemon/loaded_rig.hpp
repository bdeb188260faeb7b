// The daemon's rig: a built-in compiled in-process or a blob file from rigc,
// validated by sim_core's loader. Memory is sized once here.
#pragma once

#include <string>
#include <vector>

#include "sim_core/rig/rig.hpp"

namespace sinew::firmware {

struct LoadedRig {
  std::vector<uint64_t> blob;  // 8-byte aligned
  std::vector<uint64_t> arena;
  rig::Rig rig;
  std::vector<std::string> input_names;  // "<joint>.<dof>"
};

bool load_rig(const std::string& builtin, const std::string& blob_path, LoadedRig* out, std::string* error);

}  // namespace sinew::firmware
