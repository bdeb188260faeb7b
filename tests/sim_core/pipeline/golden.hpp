// Committed golden hashes of the pipeline workload. A numerics change
// updates these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kArmLayersBlob = 0xeaf1f6e454d9e2bdu;
inline constexpr uint64_t kPipelineArmAllLayers = 0xd501cd7c8860e443u;
}  // namespace sinew::test::golden
