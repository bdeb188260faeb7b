// Committed golden hashes of the pipeline workload. A numerics change
// updates these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kArmLayersBlob = 0x3da099c33ec18807u;
inline constexpr uint64_t kPipelineArmAllLayers = 0x9d2ab5c861755c5eu;
}  // namespace sinew::test::golden
