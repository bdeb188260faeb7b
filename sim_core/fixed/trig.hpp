// Trigonometry on binary angles (2^32 = one turn). Pure integer, identical
// bits on every platform. Measured errors are tabled in docs/numerics.md.
#pragma once

#include <cstdint>

#include "q_formats.hpp"

namespace sinew::fx {

struct SinCos {
  Unit sin;
  Unit cos;
};

// sin and cos in Q2.30 (exact to within 1 LSB of the correctly rounded value).
SinCos sin_cos(Angle a);
inline Unit sin_unit(Angle a) { return sin_cos(a).sin; }
inline Unit cos_unit(Angle a) { return sin_cos(a).cos; }

// atan2(y, x) as a binary angle; y and x share any Q format. atan2(0, 0) = 0.
Angle atan2_angle(int32_t y, int32_t x);

// Signed view of a binary angle: (-half turn, half turn].
inline int32_t angle_signed(Angle a) { return static_cast<int32_t>(a); }

// Degrees in Q16.16 <-> binary angle, for configs and logs (exact integer math).
Angle angle_from_deg_q16(int32_t deg_q16);
int32_t angle_to_deg_q16(Angle a);

}  // namespace sinew::fx
