// Committed golden hash of the sph layer's determinism workload. A numerics
// change (sim_core/sph or its builder) updates it on purpose, in a commit of
// its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kSphArm = 0x2a15692baa72d32au;
// The same workload with surface_tension = 1 N/m (SphDeterminism, second test).
inline constexpr uint64_t kSphArmSurfaceTension = 0x57603bad13161757u;
}  // namespace sinew::test::golden
