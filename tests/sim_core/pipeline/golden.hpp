// Committed golden hashes of the pipeline workload. A numerics change
// updates these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kArmLayersBlob = 0xe5c393054aa92a72u;
inline constexpr uint64_t kPipelineArmAllLayers = 0x3ccdc59abec8348fu;
}  // namespace sinew::test::golden
