// Double -> fixed-point conversions used offline: hal/units' (the one home of
// boundary conversions: exact, round half up, saturating), as the plain int32
// the rig compiler stores. Callers validate for NaN first (NaN gives 0).
#pragma once

#include <cmath>
#include <cstdint>

#include "hal/units/float_to_fixed.hpp"

namespace sinew::rigc {

inline int32_t to_fixed(double v, int frac_bits) { return units::to_fixed(v, frac_bits).value; }

// Length in model units -> Len (Q12.20) in rig units of 2^e model units.
inline int32_t to_len(double v, int32_t e) { return units::to_len(v, e).value; }
inline double from_len(int32_t v, int32_t e) { return units::len_to_double(v, e); }

// Degrees -> signed binary angle (2^32 = one turn) in (-180, 180]: +180
// gives INT32_MAX, so a limit range [lo, 180] stays ordered.
inline int32_t to_angle(double degrees) { return units::signed_angle_from_degrees(degrees).value; }

}  // namespace sinew::rigc
