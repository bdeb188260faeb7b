// Golden hashes of the metaballs determinism workload. They change only on
// purpose, in their own commit, saying why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {

inline constexpr uint64_t kMetaballsModel = 0x43f3aceefacdc74aull;
inline constexpr uint64_t kMetaballsArm = 0xe0cbcfe8286f4ff0ull;
inline constexpr uint64_t kMetaballsPhysicalModel = 0xbac13f6bf63b76fcull;
inline constexpr uint64_t kMetaballsPhysicalArm = 0x3b14bfd15db261e9ull;

}  // namespace sinew::test::golden
