// Golden hashes of the metaballs determinism workload. They change only on
// purpose, in their own commit, saying why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {

inline constexpr uint64_t kMetaballsModel = 0x43f3aceefacdc74aull;
inline constexpr uint64_t kMetaballsArm = 0xbb87c7e49d5344b1ull;

}  // namespace sinew::test::golden
