// Golden hashes of the metaballs determinism workload. They change only on
// purpose, in their own commit, saying why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {

inline constexpr uint64_t kMetaballsModel = 0xa44bae9d74d4b2bcull;
inline constexpr uint64_t kMetaballsArm = 0x81aec268a771d33cull;
inline constexpr uint64_t kMetaballsPhysicalModel = 0x594e54f392db4e4cull;
inline constexpr uint64_t kMetaballsPhysicalArm = 0x3eadb1bd73328490ull;

}  // namespace sinew::test::golden
