// Committed golden hash of the sph layer's determinism workload. A numerics
// change (sim_core/sph or its builder) updates it on purpose, in a commit of
// its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kSphArm = 0x5bbf1dd0a2616594u;
// The same workload with surface_tension = 1 N/m (SphDeterminism, second test).
inline constexpr uint64_t kSphArmSurfaceTension = 0x2aadba8b647e85b3u;
}  // namespace sinew::test::golden
