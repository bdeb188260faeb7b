// Committed golden hashes of the pipeline workload. A numerics change
// updates these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kArmLayersBlob = 0x47ab257f86b1fbaau;
inline constexpr uint64_t kPipelineArmAllLayers = 0xa6f4d986cb488a43u;
}  // namespace sinew::test::golden
