// Boundary conversions between host floating point and sinew's fixed-point
// formats (docs/numerics.md, "Boundary conversions"). sim_core never sees a
// double: every value from a config file, a model or a sensor driver is
// converted here, once, with the project's rounding rule.
//
// Every conversion is total and deterministic: the double is read from its
// bits and converted with exact integer arithmetic, so the same double gives
// the same bits on every platform, and the result is the correctly rounded
// value (round half up: to nearest, ties toward +infinity), then saturated.
//
// Results on bad input, per function (flags in the result):
//
//   input                      Unit / Lin / Len              Angle
//   exact multiple of the LSB  value, kOk                    value, kOk
//   between two values         nearest (ties up), kRounded   nearest (ties up), kRounded
//   rounds outside the range   INT32_MAX / INT32_MIN,        never: angles wrap
//     (including huge)           kClamped                      (370 deg = 10 deg)
//   +-0.0, +-denormal          0, kOk / 0, kRounded          0, kOk / 0, kRounded
//   NaN                        0, kNotFinite                 0, kNotFinite
//   +inf / -inf                INT32_MAX / INT32_MIN,        0, kNotFinite
//                                kNotFinite | kClamped
#pragma once

#include <cstdint>

namespace sinew::units {

// How a value was converted: a bit set, kOk (no bit) when the result is
// exactly the input.
enum ConversionFlags : uint8_t {
  kOk = 0,
  // In range but not a multiple of the resolution: the result is the nearest
  // representable value, ties toward +infinity. Never set with kClamped.
  kRounded = 1u << 0,
  // The rounded input lies outside the format's range: the result is the
  // nearest end (INT32_MAX or INT32_MIN).
  kClamped = 1u << 1,
  // NaN or an infinity.
  kNotFinite = 1u << 2,
};

constexpr ConversionFlags operator|(ConversionFlags a, ConversionFlags b) {
  return static_cast<ConversionFlags>(static_cast<uint8_t>(a) | static_cast<uint8_t>(b));
}

// A Unit, Lin or Len value.
struct FixedResult {
  int32_t value;
  ConversionFlags flags;
  constexpr bool ok() const { return flags == kOk; }
  constexpr bool has(ConversionFlags f) const { return (flags & f) != 0; }
};

// A binary angle (2^32 = one turn).
struct AngleResult {
  uint32_t value;
  ConversionFlags flags;
  constexpr bool ok() const { return flags == kOk; }
  constexpr bool has(ConversionFlags f) const { return (flags & f) != 0; }
};

// --- double -> fixed ----------------------------------------------------

// Any Qm.n format held in an int32: round_half_up(x * 2^frac_bits), exactly,
// then saturated (to_unit, to_lin and to_len are this with their n). Any
// frac_bits: a negative one scales down (x = 1024, frac_bits = -4 gives 64).
FixedResult to_fixed(double x, int32_t frac_bits);

// Unit, Q2.30: range [-2, 2), resolution 2^-30. Inputs in [2 - 2^-31, +inf)
// round to 2^31 and clamp to INT32_MAX; inputs in [-2 - 2^-31, -2) round to
// INT32_MIN (kRounded, not kClamped); below that, kClamped.
FixedResult to_unit(double x);

// Lin, Q8.24: range [-128, 128), resolution 2^-24. Same edges scaled by 2^6.
FixedResult to_lin(double x);

// Len, Q12.20 rig units, for a length `x` in source units (metres or model
// units) when one rig unit is 2^length_exponent source units (the rig's
// length exponent): the value is round(x * 2^(20 - length_exponent)), range
// [-2048, 2048) rig units. Any int32 exponent is accepted; extreme exponents
// just clamp (large x) or round to 0 (small x).
FixedResult to_len(double x, int32_t length_exponent);

// Binary angle from degrees: round(deg * 2^32 / 360) modulo 2^32. Exact: the
// input is first reduced modulo 360 (exactly, std::fmod), so huge inputs give
// the correctly rounded angle of their true value, never a clamp. kOk when
// deg is a multiple of 360 / 2^32 (e.g. every angle_to_degrees output).
AngleResult angle_from_degrees(double deg);

// Signed binary angle from degrees, for ranges and limits: the int32 view of
// angle_from_degrees (so in [-180, 180) degrees), except that an input equal
// to +180 modulo 360 gives INT32_MAX (180 - 2^-32 turn, flagged kClamped)
// rather than wrapping to -180, so a range [lo, 180] keeps its upper end
// above its lower end. NaN and infinities: 0, kNotFinite.
FixedResult signed_angle_from_degrees(double deg);

// Binary angle from radians: round(rad * 2^31 / pi) modulo 2^32, correctly
// rounded for every finite double (reduction with 1216 bits of 1/(2 pi)).
// pi is irrational, so every nonzero input is kRounded (and never a tie).
AngleResult angle_from_radians(double rad);

// --- fixed -> double, for tools and logs ----------------------------------

// Exact: value * 2^-frac_bits (any Q format; frac_bits in [-1000, 1000]).
double fixed_to_double(int32_t value, int32_t frac_bits);

// Exact.
double unit_to_double(int32_t unit);
double lin_to_double(int32_t lin);

// value * 2^(length_exponent - 20) source units. Exact unless the result
// leaves double's normal range (only for |length_exponent| beyond ~1000,
// where it underflows towards 0 or overflows to +-inf).
double len_to_double(int32_t len, int32_t length_exponent);

// The signed view of the angle (as fx::angle_signed): degrees in [-180, 180).
// Exact, so angle_from_degrees(angle_to_degrees(a)) is {a, kOk}.
double angle_to_degrees(uint32_t angle);

// Radians in [-pi, pi), within 1 ulp; angle_from_radians gives `angle` back
// (flagged kRounded, as every nonzero radian input is).
double angle_to_radians(uint32_t angle);

}  // namespace sinew::units
