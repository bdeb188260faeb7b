// Committed golden hash of the anatomy determinism workload. A numerics
// change updates it on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kAnatomyArm = 0xdcc79fea7d1b0bdeu;
// The same workload with the dynamic skin (LEMAN §3) at 1 kHz.
inline constexpr uint64_t kAnatomyArmDynamic = 0x1c7b64a75e7be7d8u;
}  // namespace sinew::test::golden
