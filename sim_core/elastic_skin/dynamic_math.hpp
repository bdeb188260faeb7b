// Fixed-point arithmetic and per-step gains shared by the dynamic skin's
// two integrators (skin_dynamic.cpp: explicit substeps; surface_relaxation.cpp:
// LEMAN §6.11's implicit relaxation). Internal to sim_core/elastic_skin.
#pragma once

#include <bit>
#include <cstdint>
#include <span>

#include "invariant_division.hpp"
#include "relaxation.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "sim_core/fixed/wide.hpp"
#include "skin_model.hpp"

namespace sinew::elastic_skin::dynamic {

// Within a tick the integrator works in the substep's own units: each
// vertex carries d = v h, its displacement per substep (Q28.36 rig units,
// held in SkinState::velocity between the tick's start and end), and every
// gain is premultiplied by h or h^2, so a substep has no division:
//   d' = (d + h^2 a + sum_i (h c_i / m) d_i) / (1 + h D),  x' = x + d'
// which is the integrator of skin_model.hpp multiplied through by h.
inline constexpr int64_t kMotionLimit = int64_t{1} << 46;        // |v|, Q44.20 rig units / s (between ticks)
inline constexpr int64_t kDisplacementLimit = int64_t{1} << 50;  // |d| and |h^2 a|, Q28.36: 16384 units, past any Len
inline constexpr int kFineExtraBits = 16;                        // Q28.36 fine positions over Q12.20 Len
inline constexpr int kGainFracBits = 30;                         // h^2 k / m and h c / m, dimensionless, Q30
inline constexpr int kSpringFracBits = 46;                       // h^2 * stiffness_scale / m per unit model stiffness
inline constexpr int64_t kFineMax = int64_t{INT32_MAX} << kFineExtraBits;
inline constexpr int64_t kFineMin = int64_t{INT32_MIN} << kFineExtraBits;
inline constexpr int64_t kSaturated = int64_t{1} << 62;
inline constexpr uint32_t kStartRelaxations = 30;  // the first step's settling (§5.2: "about 30")

inline int64_t clamp_motion(int64_t v) { return fx::clamp_i64(v, -kMotionLimit, kMotionLimit); }
inline int64_t clamp_displacement(int64_t d) { return fx::clamp_i64(d, -kDisplacementLimit, kDisplacementLimit); }

// round_half_up(a * b / 2^shift), saturated to +-2^62 rather than
// overflowing. Operands whose bit widths sum to 62 or less multiply in 64
// bits (the same rounding: floor((a b + 2^(shift-1)) / 2^shift) either way);
// only wider ones, which the skin's gains rarely reach, take the 128-bit
// product, out of line so the common case stays small enough to inline.
[[gnu::noinline]] inline int64_t mul_shift_wide_sat(int64_t a, int64_t b, int shift) {
  const fx::U128 p = fx::mul_u64(fx::magnitude(a), fx::magnitude(b));
  if ((p.hi >> (shift - 2)) != 0) return (a < 0) != (b < 0) ? -kSaturated : kSaturated;
  return fx::mul_shift_round(a, b, shift);
}

[[gnu::always_inline]] inline int64_t mul_shift_sat(int64_t a, int64_t b, int shift) {
  if (std::bit_width(fx::magnitude(a)) + std::bit_width(fx::magnitude(b)) <= 62) return fx::round_shift(a * b, shift);
  return mul_shift_wide_sat(a, b, shift);
}

// round(x * 2^shift / h_inv), saturated to +-2^62; x >= 0, 1 <= shift <= 32.
inline int64_t per_substep(int64_t x, int shift, int64_t h_inv) {
  if (x <= (kSaturated >> shift)) return fx::div_round(x << shift, h_inv);
  const int64_t q = fx::div_round(x, h_inv);  // x > 2^(62 - shift): q keeps 30+ significant bits
  return q > (kSaturated >> shift) ? kSaturated : q << shift;
}

// h^2 k / m of a model stiffness k (Q16.16), Q30.
[[gnu::always_inline]] inline int64_t spring_gain(int64_t k, int64_t spring_h2) {
  return mul_shift_sat(k, spring_h2, kStiffnessFracBits + kSpringFracBits - kGainFracBits);
}

// The spring of edge e (eq. 1, with the §5.2 push-back for compressed
// edges) as the displacement it adds to its endpoint a in one substep,
// h^2 a, Q28.36 rig units per component (b gets the opposite):
//   h^2 k' spring (|w| - rest) / |w| w,  w = x_b - x_a.
// (|w| - rest) / |w| = 1 - rest / |w| takes 1 / |w| from the
// division-free reciprocal square root (relative error ~1e-9); only a
// compressed edge, whose push-back multiplier needs the excess itself,
// takes the exact root. rest_gain is spring_gain(e.k, spring_h2), the
// gain of an edge not compressed (a step's constant). False when the edge
// pulls with nothing.
[[gnu::always_inline]] inline bool edge_displacement(const SkinParams& p, const Edge& e, int64_t spring_h2,
                                                     int64_t rest_gain, const std::span<fx::Len> (&position)[3],
                                                     int64_t out[3]) {
  int64_t w[3];
  uint64_t n2 = 0;
  for (int c = 0; c < 3; ++c) {
    w[c] = fx::sat_i32(int64_t{position[c][e.b]} - position[c][e.a]);
    const uint64_t m = fx::magnitude(w[c]);
    n2 += m * m;  // each <= 2^62: the sum < 2^64
  }
  if (n2 == 0 || e.k == 0) return false;
  const EdgeSpring spring = edge_spring(p, e, n2);
  const int64_t ratio = spring.ratio, k = spring.k;
  if (k == 0) return false;
  // h^2 k' spring, Q30 (<= 1 on a stable step); times the ratio, Q30. Not
  // compressed, k' is e.k (edge_spring).
  const int64_t gain = mul_shift_sat(ratio >= 0 ? rest_gain : spring_gain(k, spring_h2), ratio, fx::kUnitFracBits);
  // Q30 x Q12.20 -> Q28.36.
  for (int c = 0; c < 3; ++c)
    out[c] = clamp_displacement(mul_shift_sat(gain, w[c], kGainFracBits + 20 - 20 - kFineExtraBits));
  return true;
}

[[gnu::always_inline]] inline bool edge_displacement(const SkinParams& p, const Edge& e, int64_t spring_h2,
                                                     const std::span<fx::Len> (&position)[3], int64_t out[3]) {
  return edge_displacement(p, e, spring_h2, spring_gain(e.k, spring_h2), position, out);
}

// The tick's gains in substep units (h = 1 / H).
struct Gains {
  int64_t spring_h2 = 0;     // h^2 stiffness_scale / m, Q46 per unit of model stiffness (Q16.16)
  int64_t anchor_gamma = 0;  // h anchor_damping / m, Q30
  int64_t band_gamma = 0;    // h band_damping / m, Q30
  int64_t edge_gamma = 0;    // h edge_damping / m, Q30
  int64_t external[3] = {};  // h^2 (gravity - a_base), Q28.36
  // 1 / (1 + h c_anchor / m), Q30: the implicit-dashpot factor of every
  // vertex without rubber bands.
  int64_t anchor_only_factor = 0;
  InvariantDivisor by_substeps;  // n
};

// 1 / (1 + beta), Q30, for beta = h D >= 0 in Q30.
inline int64_t damping_factor(int64_t beta_q30) {
  return fx::div_round(int64_t{1} << (2 * kGainFracBits), fx::add_sat_i64(int64_t{1} << kGainFracBits, beta_q30));
}

}  // namespace sinew::elastic_skin::dynamic
