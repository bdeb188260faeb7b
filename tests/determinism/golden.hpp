// Committed golden hashes. A numerics change updates these on purpose, in a
// commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kFixedOps = 0x2b9630ad9245678au;
inline constexpr uint64_t kArmBlob = 0xc2e4e3a3462b0916u;
inline constexpr uint64_t kEngineArm = 0x05f78564529e4deeu;
inline constexpr uint64_t kHandBlob = 0x2179c8a2f40fe1ceu;
inline constexpr uint64_t kEngineHand = 0xfb1afb98c6e998c1u;
}  // namespace sinew::test::golden
