// Committed golden hashes of the pipeline workload. A numerics change
// updates these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kArmLayersBlob = 0xd568cad81189c4a7u;
inline constexpr uint64_t kPipelineArmAllLayers = 0x8418ef96f17cab13u;
}  // namespace sinew::test::golden
