// Exact range reduction of radians to turns (Payne-Hanek): the fraction of a
// turn of mantissa * 2^exponent radians, to 192 bits, from a table of the
// bits of 1/(2 pi). Integer-only, so identical on every platform.
#pragma once

#include <cstdint>

namespace sinew::units::detail {

// frac(mantissa * 2^exponent / (2 pi)) * 2^192, as three 64-bit words,
// most significant first; truncated by less than 2^-139 turn. Valid for any
// mantissa < 2^53 and exponent <= 971 (every finite double).
struct TurnFraction {
  uint64_t word[3];
};

TurnFraction turns_of_radians(uint64_t mantissa, int exponent);

}  // namespace sinew::units::detail
