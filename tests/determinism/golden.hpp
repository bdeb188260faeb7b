// Committed golden hashes. A numerics change updates these on purpose, in a
// commit of its own that says why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {
inline constexpr uint64_t kFixedOps = 0x2b9630ad9245678au;
inline constexpr uint64_t kArmBlob = 0x5b2eb764fd9bae86u;
inline constexpr uint64_t kEngineArm = 0x48ef78c184c6b532u;
inline constexpr uint64_t kHandBlob = 0xa099ab45c5e37aecu;
inline constexpr uint64_t kEngineHand = 0x505f5e54fc2dca0au;
}  // namespace sinew::test::golden
