// Q formats of sinew's simulation state. Every quantity in sim_core is one of
// these; docs/numerics.md tables them with range, resolution and the measured
// error of every function.
//
//   Unit   int32  Q2.30   unit quantities: quaternion components, weights,
//                         normals, pure-rotation entries.     [-2, 2), 2^-30
//   Lin    int32  Q8.24   general linear parts of affine transforms (rotation
//                         times scale): glTF nodes may scale.  [-128, 128), 2^-24
//   Len    int32  Q12.20  lengths and positions in rig units. [-2048, 2048), 2^-20
//                         A rig stores a power-of-two unit exponent so that a
//                         rig unit is 2^e metres (or glTF units); a 20 cm hand
//                         at e = 0 has ~1 um steps (Q16.16's 15 um is too coarse).
//   Angle  uint32         binary angle, 2^32 = one turn; wraps by definition.
//   Wide   int64          accumulators of products.
//
// Rounding: every narrowing shift rounds to nearest, ties toward +infinity
// ("round half up"): (v + 2^(s-1)) >> s with C++20's arithmetic right shift.
// Overflow: every narrowing to 32 bits saturates; the counting overloads add
// one to a Saturation counter per clamped value. Signed overflow never happens.
#pragma once

#include <cstdint>

namespace sinew::fx {

using Unit = int32_t;
using Lin = int32_t;
using Len = int32_t;
using Angle = uint32_t;

inline constexpr int kUnitFracBits = 30;
inline constexpr int kLinFracBits = 24;
inline constexpr int kLenFracBits = 20;

inline constexpr Unit kUnitOne = int32_t{1} << kUnitFracBits;
inline constexpr Lin kLinOne = int32_t{1} << kLinFracBits;
inline constexpr Len kLenOne = int32_t{1} << kLenFracBits;

inline constexpr Angle kQuarterTurn = Angle{1} << 30;
inline constexpr Angle kHalfTurn = Angle{1} << 31;

}  // namespace sinew::fx
