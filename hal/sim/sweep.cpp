#include "hal/sim/sweep.hpp"

#include "sim_core/fixed/trig.hpp"

namespace sinew::hal::sim {

int32_t sweep_input(uint32_t input, uint32_t step) {
  // Amplitude 120 degrees, a different period per input (prime multiples).
  const fx::Angle phase = static_cast<fx::Angle>(step * (2654435u + 977u * input) + input * 0x3C6EF372u);
  const int64_t amplitude = int64_t{1} << 30;  // one third of a turn, ~120 degrees
  return static_cast<int32_t>((amplitude * fx::sin_unit(phase)) >> fx::kUnitFracBits);
}

}  // namespace sinew::hal::sim
