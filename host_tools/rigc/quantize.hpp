// Double -> fixed-point conversions used offline (round half up, saturating).
#pragma once

#include <cmath>
#include <cstdint>

namespace sinew::rigc {

inline int32_t to_fixed(double v, int frac_bits) {
  const double scaled = std::floor(std::ldexp(v, frac_bits) + 0.5);
  if (!(scaled == scaled)) return 0;  // NaN: callers validate first
  if (scaled >= 2147483647.0) return INT32_MAX;
  if (scaled <= -2147483648.0) return INT32_MIN;
  return static_cast<int32_t>(scaled);
}

// Length in model units -> Len (Q12.20) in rig units of 2^e model units.
inline int32_t to_len(double v, int32_t e) { return to_fixed(std::ldexp(v, -e), 20); }
inline double from_len(int32_t v, int32_t e) { return std::ldexp(static_cast<double>(v), e - 20); }

// Degrees -> signed binary angle (2^32 = one turn), wrapped into (-180, 180].
inline int32_t to_angle(double degrees) {
  double turns = degrees / 360.0;
  turns -= std::floor(turns + 0.5);
  return to_fixed(turns, 32);
}

}  // namespace sinew::rigc
