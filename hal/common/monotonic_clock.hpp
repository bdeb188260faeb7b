// CLOCK_MONOTONIC in nanoseconds: the time base of every sample timestamp,
// tick deadline and timeout in sinew (GPIO edge events are stamped on it;
// SocketCAN's CLOCK_REALTIME stamps are converted to it on arrival).
#pragma once

#include <cstdint>

namespace sinew::hal {

uint64_t monotonic_ns();

}  // namespace sinew::hal
