// CLOCK_MONOTONIC in nanoseconds: the time base of every sample timestamp,
// tick deadline and timeout in sinew (kernel CAN/GPIO timestamps use it too).
#pragma once

#include <cstdint>

namespace sinew::hal {

uint64_t monotonic_ns();

}  // namespace sinew::hal
