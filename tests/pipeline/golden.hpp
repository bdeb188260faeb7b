// Committed golden hashes of the pipeline workload. A numerics change
// updates these on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kArmLayersBlob = 0x37eff3df23287b0eu;
inline constexpr uint64_t kPipelineArmAllLayers = 0x6c12e55b0edbfccdu;
}  // namespace sinew::test::golden
