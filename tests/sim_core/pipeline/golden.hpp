// Committed golden hashes of the pipeline workload. A numerics change
// updates these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kArmLayersBlob = 0x6765619d024149e9u;
inline constexpr uint64_t kPipelineArmAllLayers = 0x57af190b0b229f00u;
}  // namespace sinew::test::golden
