// The deterministic sweep every simulated input source shares: input i at
// step s, a signed binary angle of amplitude 2^30 (a third of a turn, ~120
// degrees), each input at its own period (prime multiples) and phase. The
// daemon's trajectory source rescales it to each joint's range; the engine
// determinism workload feeds it to the engine as is, so its values are part
// of the golden hashes and must never change. Integer math only.
#pragma once

#include <cstdint>

namespace sinew::hal::sim {

int32_t sweep_input(uint32_t input, uint32_t step);

}  // namespace sinew::hal::sim
