// The general superquadric primitive (LEMAN §5.2, §6.11; [Barr 81]): any
// pair of exponents in [1, 16] (PrimitiveExponents), evaluated in the log
// domain with sim_core/fixed/log_exp. Equal exponents 2, 4 and 8 keep the
// exact integer kernel of primitive.cpp; this one runs for every other pair.
//
// With q = (x/a, y/b, z/c), X = |qx|^p_xy, Y = |qy|^p_xy, S = X + Y,
// e = p_z / p_xy, Z = |qz|^p_z:
//   F = S^e + Z                                   (inside when F < 1)
//   dF/dx = p_z S^(e-1) |qx|^(p_xy-1) sign(qx) / a  (y alike with b)
//   dF/dz = p_z |qz|^(p_z-1) sign(qz) / c
// Each factor is one power of two of a sum of logarithms, e.g. for x:
//   L_x = (e - 1) log2 S + (p_xy - 1) log2|qx| + log2(emax / a),
// so no intermediate power can underflow or overflow. The direction is
// 2^(L_i - M) with M = max L_i (its largest component exactly 2^30, the
// others below): it keeps full precision even deep inside, where every
// factor is tiny (for p = 16 at q = 0.1 they are 1e-15). Inside F < 1 the
// factors are at most 1 (X <= S gives S^(e-1) X^((p_xy-1)/p_xy) <=
// S^((p_z-1)/p_xy) <= 1 as S < 1 and p_z >= 1), so |grad F| emax <=
// sqrt(3) p_z emax / min extent: gradient_length's Len format holds it for
// any validated primitive (aspect <= 64).
//
// F is homogeneous of degree p_z, so G = F^(1/p_z) grows linearly along
// rays (the push-out's Newton function); G is a nested norm
// (|| (|| (x/a, y/b) ||_p_xy, z/c) ||_p_z) and so convex for exponents >= 1:
// a Newton step along grad G from inside lands on or outside the surface.
//
// Accuracy, derived from the Q formats (u = 2^-30) and enforced against a
// double oracle of Barr's formula in tests/sim_core/elastic_skin/superquadric_test.cpp.
// Each log2|q_i| is off by at most u (two correctly rounded logarithms; their
// kernels' 2^-16 u is lost in the slack below), log2 S by (p_xy + 1) u; each
// product with a Q16.16 power and each log2(2^a + 2^b) adds u/2; e (Q58)
// adds nothing visible; exp2 rounds by half an LSB. So
//   - log2 of each term of F (S^e, Z) is off by at most (p_z + e + 1/2) u,
//     and F, the sum of the two terms each rounded to Q2.30, by
//     |F - F_Barr| <= [ln 2 (p_z + e + 1/2) F + 1.01] u;
//   - each gradient exponent L_i by at most
//     dL = max(|e - 1| (p_xy + 1) + p_xy + 1, p_z + 1/2) u, so the direction
//     (ratios of components, rounded to Q2.30 and normalised) is within
//     (2 ln 2 dL + 6) u of Barr's gradient.
#pragma once

#include <cstdint>

#include "muscle_state.hpp"

namespace sinew::muscle {

// True when the frame takes the general kernel: a superellipsoid whose
// exponent is not 2, 4 or 8 (the record's 0).
inline bool is_general_superquadric(const PrimitiveFrame& f) {
  return f.kind == static_cast<uint8_t>(PrimitiveKind::kSuperellipsoid) && f.exponent != 2 && f.exponent != 4 &&
         f.exponent != 8;
}

// Sets f->superquadric's derived terms from its powers and f->extent (call
// after either changes; muscle_step does, once per step).
void superquadric_prepare(PrimitiveFrame* f);

// F and its gradient at undeformed local coordinates (Len, the primitive's
// axes; |local_i| < extent_i, as primitive_sample has checked).
struct SuperquadricEval {
  bool inside = true;
  int64_t value = 0;            // F in Q2.30 (2^(log2 S^e) + 2^(log2 Z)), capped at 4 (outside)
  int64_t log2_terms[2] = {};   // log2 S^e and log2 Z, Q30 (fx::kLog2OfZero for an absent term)
  int64_t g[3] = {};            // gradient direction, local axes: largest |g_i| = 2^30; zero at the centre
  int64_t log2_largest = 0;     // the largest component's log2(|dF/dx_i| emax / p_z), Q30
  uint32_t g_length = 0;        // |g|, Q30 (in [2^30, sqrt(3) 2^30] unless zero)
  int32_t gradient_length = 0;  // |grad F| emax, Q12.20 (PrimitiveSample), saturated
};
SuperquadricEval superquadric_eval(const PrimitiveFrame& f, const int64_t local[3]);

// The Newton step on G = F^(1/p_z) along the gradient, in Len LSBs:
// (1 - G) / |grad G| = p_z (1 - G) F / (G |grad F|), for an inside point
// with a non-zero gradient (0 when G rounds to 1). Saturates at INT64_MAX.
int64_t superquadric_newton_step(const PrimitiveFrame& f, const SuperquadricEval& e);

}  // namespace sinew::muscle
