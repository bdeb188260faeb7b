#include "trig.hpp"

#include "scalar.hpp"
#include "wide.hpp"

namespace sinew::fx {
namespace {

// Kernels work in Q62 (|v| < 2) for headroom far below the Q30 output LSB.
constexpr int64_t kOneQ62 = int64_t{1} << 62;
constexpr int64_t kPiQ61 = 0x6487ED5110B4611A;          // pi * 2^61
constexpr uint64_t kInvTwoPiQ64 = 0x28BE60DB9391054Au;  // 1/(2 pi) * 2^64
constexpr int64_t kQuarterPiQ62 = 0x3243F6A8885A308D;   // pi/4 * 2^62

inline int64_t mul_q62(int64_t a, int64_t b) { return mul_shift_round(a, b, 62); }

// sin(t), cos(t) for 0 <= t <= pi/4 in Q62 by nested Taylor factors:
// sin = t(1 - u/(2*3)(1 - u/(4*5)(...))), u = t^2; the first omitted term is
// below 3e-14, far under the Q30 output step (9.3e-10).
int64_t sin_kernel(int64_t t) {
  const int64_t u = mul_q62(t, t);
  int64_t p = kOneQ62;
  for (int64_t k = 14; k >= 2; k -= 2) p = kOneQ62 - mul_q62(u, p) / (k * (k + 1));
  return mul_q62(t, p);
}

int64_t cos_kernel(int64_t t) {
  const int64_t u = mul_q62(t, t);
  int64_t p = kOneQ62;
  for (int64_t k = 15; k >= 1; k -= 2) p = kOneQ62 - mul_q62(u, p) / (k * (k + 1));
  return p;
}

inline Unit q62_to_unit(int64_t v) { return sat_i32(round_shift(v, 32)); }

// n / d in Q62 for 0 <= n <= d, 0 < d <= 2^33, by two exact long-division steps.
int64_t ratio_q62(uint64_t n, uint64_t d) {
  const uint64_t q1 = (n << 30) / d;
  const uint64_t r1 = (n << 30) % d;
  const uint64_t q2 = (r1 << 30) / d;
  const uint64_t r2 = (r1 << 30) % d;
  const uint64_t q3 = (r2 << 2) / d;
  return static_cast<int64_t>((q1 << 32) | (q2 << 2) | q3);
}

// atan(w) for |w| <= 1/2 in Q62: w * sum (-u)^k / (2k+1), u = w^2, 22 terms.
int64_t atan_kernel(int64_t w) {
  const int64_t u = mul_q62(w, w);
  int64_t p = 0;
  for (int64_t k = 21; k >= 0; --k) p = kOneQ62 / (2 * k + 1) - mul_q62(u, p);
  return mul_q62(w, p);
}

}  // namespace

SinCos sin_cos(Angle a) {
  const uint32_t quadrant = a >> 30;
  uint32_t r = a & (kQuarterTurn - 1);
  const bool mirrored = r > (kQuarterTurn >> 1);
  if (mirrored) r = kQuarterTurn - r;
  // t = r * 2pi / 2^32 in Q62 = r * pi * 2^31 = r * (pi * 2^61) / 2^30.
  const int64_t t = mul_shift_round(int64_t{r}, kPiQ61, 30);
  Unit s = q62_to_unit(sin_kernel(t));
  Unit c = q62_to_unit(cos_kernel(t));
  if (mirrored) {
    const Unit tmp = s;
    s = c;
    c = tmp;
  }
  switch (quadrant) {
    case 0:
      return {s, c};
    case 1:
      return {c, -s};
    case 2:
      return {-s, -c};
    default:
      return {-c, s};
  }
}

Angle atan2_angle(int32_t y, int32_t x) {
  if (x == 0 && y == 0) return 0;
  uint64_t ax = magnitude(x);
  uint64_t ay = magnitude(y);
  const bool swapped = ay > ax;
  if (swapped) {
    const uint64_t tmp = ax;
    ax = ay;
    ay = tmp;
  }
  // 0 <= ay <= ax: reduce to |w| <= 1/2 with atan(z) = pi/4 + atan((z-1)/(z+1)).
  int64_t t;
  if (2 * ay > ax) {
    t = kQuarterPiQ62 - atan_kernel(ratio_q62(ax - ay, ax + ay));
  } else {
    t = atan_kernel(ratio_q62(ay, ax));
  }
  // radians (Q62) -> turns * 2^32: t * (1/2pi) * 2^(32-62).
  const U128 p = mul_u64(static_cast<uint64_t>(t), kInvTwoPiQ64);
  Angle angle = static_cast<Angle>((p.hi + (uint64_t{1} << 29)) >> 30);
  if (swapped) angle = kQuarterTurn - angle;
  if (x < 0) angle = kHalfTurn - angle;
  if (y < 0) angle = Angle{0} - angle;
  return angle;
}

Angle angle_from_deg_q16(int32_t deg_q16) {
  // a = deg * 2^32 / 360 with deg in Q16.16: deg_q16 * 2^16 / 360, mod 2^32.
  const int64_t scaled = div_round(int64_t{deg_q16} * 65536, 360);
  return static_cast<Angle>(static_cast<uint64_t>(scaled));
}

int32_t angle_to_deg_q16(Angle a) { return static_cast<int32_t>(div_round(int64_t{angle_signed(a)} * 360, 65536)); }

}  // namespace sinew::fx
