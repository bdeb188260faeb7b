// Committed golden hashes of the pipeline workload. A numerics change
// updates these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kArmLayersBlob = 0x9d18c76afea3c5ffu;
inline constexpr uint64_t kPipelineArmAllLayers = 0xd85f8a23b19aee4bu;
}  // namespace sinew::test::golden
