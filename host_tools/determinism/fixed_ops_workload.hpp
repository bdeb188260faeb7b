// The fixed-point reference workload: a long chain of every sim_core/fixed
// operation with every output hashed (xxHash64 over little-endian values).
#pragma once

#include <cstdint>

namespace sinew::determinism {

uint64_t run_fixed_ops(int iterations);

inline constexpr int kFixedOpsIterations = 100000;

}  // namespace sinew::determinism
