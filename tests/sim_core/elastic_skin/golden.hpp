// Committed golden hash of the anatomy determinism workload. A numerics
// change updates it on purpose, in a commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kAnatomyArm = 0xdcd2637072daaa1au;
// The same workload with the dynamic skin (LEMAN §3) at 1 kHz.
inline constexpr uint64_t kAnatomyArmDynamic = 0xaf92dfac7beb2cd1u;
// The same workload with LEMAN's surface by relaxation, gravity and 20 Pa.
inline constexpr uint64_t kAnatomyArmRelaxation = 0xb44304fc9739645du;
// The static workload with both bellies general superquadrics (p_xy 3, p_z 2.5).
inline constexpr uint64_t kAnatomyArmSuperquadric = 0x6aa97b6c347ea6c2u;
}  // namespace sinew::test::golden
