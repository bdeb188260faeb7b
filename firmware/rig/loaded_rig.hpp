// The daemon's rig: a compiled blob (a file from rigc, or a built-in the
// firmware embeds), validated by sim_core's loaders: the core rig and the
// physical layers it carries. Memory is sized once here.
#pragma once

#include <string>
#include <vector>

#include "hal/common/blob_file.hpp"
#include "sim_core/pipeline/layer_set.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::firmware {

// An input the daemon reads besides the rig's joint DOFs, declared by the
// rig (its EXTI section): e.g. a force measured at a joint ("elbow.force",
// newtons in Q16.16). It is fed, health-checked, held and logged like a
// joint input; the skeleton does not see it, the layer that names it does.
struct ExternalInput {
  std::string name, unit;
  int32_t min = 0, max = 0;  // accepted range before the range margin, Q16.16 in `unit`
  bool force = false;        // a force in newtons (Q16.16)
};

inline constexpr size_t kMaxRigFileBytes = size_t{256} << 20;

struct LoadedRig {
  hal::BlobBytes blob;
  std::vector<uint64_t> arena, layer_arena;
  rig::Rig rig;
  pipeline::LayerSet layers;
  // "<joint>.<dof>" for the rig's inputs 0 .. rig.input_count - 1, then the
  // external inputs' names.
  std::vector<std::string> input_names;
  std::vector<ExternalInput> external;  // inputs rig.input_count onwards
  // Rig inputs that drive no joint DOF (named "input<k>"): read and logged,
  // and reported once at start, since a spec rarely means to declare them.
  std::vector<uint32_t> unused_inputs;

  uint32_t input_count() const { return static_cast<uint32_t>(input_names.size()); }
};

// builtin: "arm" / "hand" (embedded), else blob_path. Errors name the blob
// and the section and field at fault.
bool load_rig(const std::string& builtin, const std::string& blob_path, LoadedRig* out, std::string* error);

// The same from bytes already in memory (tests, tools).
bool load_rig_bytes(hal::BlobBytes bytes, const std::string& origin, LoadedRig* out, std::string* error);

// One line naming the layers the rig carries (pipeline::describe_layers).
std::string describe_layers(const LoadedRig& rig);

}  // namespace sinew::firmware
