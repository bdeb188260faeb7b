// Committed golden hash of the anatomy determinism workload. A numerics
// change updates it on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kAnatomyArm = 0xdcd2637072daaa1au;
// The same workload with the dynamic skin (LEMAN §3) at 1 kHz.
inline constexpr uint64_t kAnatomyArmDynamic = 0xc8c5749ad053aa95u;
// The same workload with LEMAN's surface by relaxation, gravity and 20 Pa.
inline constexpr uint64_t kAnatomyArmRelaxation = 0xbdd82347d35caa6au;
// The static workload with both bellies general superquadrics (p_xy 3, p_z 2.5).
inline constexpr uint64_t kAnatomyArmSuperquadric = 0xce7f7b5a00f96655u;
}  // namespace sinew::test::golden
