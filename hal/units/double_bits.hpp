// A finite double as sign, integer mantissa and power of two, read from its
// bits: the conversions below then run in exact integer arithmetic, so they
// give the same result on every platform and never depend on libm.
#pragma once

#include <bit>
#include <cstdint>

namespace sinew::units::detail {

// |x| = mantissa * 2^exponent, mantissa < 2^53 (0 for +-0.0).
struct DoubleBits {
  bool negative;
  bool finite;
  bool nan;
  uint64_t mantissa;
  int exponent;
};

inline DoubleBits double_bits(double x) {
  const uint64_t bits = std::bit_cast<uint64_t>(x);
  const auto biased = static_cast<int>((bits >> 52) & 0x7FF);
  const uint64_t fraction = bits & ((uint64_t{1} << 52) - 1);
  DoubleBits d{};
  d.negative = (bits >> 63) != 0;
  d.finite = biased != 0x7FF;
  d.nan = !d.finite && fraction != 0;
  if (biased == 0) {  // zero or subnormal
    d.mantissa = fraction;
    d.exponent = -1074;
  } else {
    d.mantissa = fraction | (uint64_t{1} << 52);
    d.exponent = biased - 1075;
  }
  return d;
}

}  // namespace sinew::units::detail
