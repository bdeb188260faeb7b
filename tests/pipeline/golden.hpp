// Committed golden hashes of the pipeline workload. A numerics change
// updates these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kArmLayersBlob = 0x1b075136204f5111u;
inline constexpr uint64_t kPipelineArmAllLayers = 0x816be84ab27b820eu;
}  // namespace sinew::test::golden
