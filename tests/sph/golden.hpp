// Committed golden hash of the sph layer's determinism workload. A numerics
// change (sim_core/sph or its builder) updates it on purpose, in a commit of
// its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kSphArm = 0xbe718026777d5b5au;
}  // namespace sinew::test::golden
