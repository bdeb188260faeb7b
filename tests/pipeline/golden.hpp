// Committed golden hashes of the pipeline workload. A numerics change
// updates these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kArmLayersBlob = 0x13cb7325f611e53cu;
inline constexpr uint64_t kPipelineArmAllLayers = 0x10b7b3ff7a2ba757u;
}  // namespace sinew::test::golden
