// Committed golden hashes of the pipeline workload. A numerics change
// updates these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kArmLayersBlob = 0xd568cad81189c4a7u;
inline constexpr uint64_t kPipelineArmAllLayers = 0xc1e25ea39ea3a1cfu;
}  // namespace sinew::test::golden
