// Golden hashes of the metaballs determinism workload. They change only on
// purpose, in their own commit, saying why.
#pragma once

#include <cstdint>

namespace sinew::test::golden {

inline constexpr uint64_t kMetaballsModel = 0xcca36821757762b4ull;
inline constexpr uint64_t kMetaballsArm = 0x81aec268a771d33cull;
inline constexpr uint64_t kMetaballsPhysicalModel = 0xd137989fdfa45042ull;
inline constexpr uint64_t kMetaballsPhysicalArm = 0xdeb7691daad16e11ull;

}  // namespace sinew::test::golden
