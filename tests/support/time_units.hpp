// Time units of the hal and firmware tests: sample and tick times are
// CLOCK_MONOTONIC nanoseconds.
#pragma once

#include <cstdint>

namespace sinew::test {

inline constexpr uint64_t kUs = 1'000;      // nanoseconds per microsecond
inline constexpr uint64_t kMs = 1'000'000;  // nanoseconds per millisecond

}  // namespace sinew::test
