// Physical values (degrees, radians, rig units) to the engine's integer
// formats (docs/numerics.md): a rotation becomes a binary angle (2^32 = one
// turn, wrapping, shown signed), a translation Q12.20 rig units. The
// arithmetic is hal/units' (the one home of boundary conversions): correctly
// rounded, half up.
#pragma once

#include <cstdint>

namespace sinew::hal::can {

enum class PhysicalUnit : uint8_t {
  kDegrees,
  kRadians,
  kRigUnits,  // translational input, in the rig's length unit
};

// Largest magnitude representable as Q12.20 (exclusive upper end 2048).
inline constexpr double kRigUnitsLimit = 2048.0;

// False (out unchanged) when `physical` is not finite or, for rig units,
// outside [-2048, 2048 - 2^-20] after rounding. Angles always convert.
bool to_engine_value(double physical, PhysicalUnit unit, int32_t& out);

// The inverse, for tests and reports.
double from_engine_value(int32_t value, PhysicalUnit unit);

}  // namespace sinew::hal::can
