// Committed golden hashes of the pipeline workload. A numerics change
// updates these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kArmLayersBlob = 0xe322104d09c54a42u;
inline constexpr uint64_t kPipelineArmAllLayers = 0x8beec896e5a7c8f8u;
}  // namespace sinew::test::golden
