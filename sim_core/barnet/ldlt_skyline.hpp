// Fixed-point LDL^T factorisation of the bar-net matrix D = C^T Q C (eq. (3)
// of barnet-driven-skinning's appendix) in skyline (envelope) storage, and
// the per-step solve D x = b. Factorised once at init; the solve touches only
// the profile, allocates nothing and does a fixed amount of work.
//
// Storage: row i of L holds columns [first[i], i) at lower[offset[i] ...];
// the unit diagonal is implied. D is symmetric, weakly diagonally dominant
// with non-positive off-diagonal entries (an M-matrix once every free node
// reaches a fixed node), so every |L_ij| <= 1 and every pivot d_i >= q_min / n
// (d_i is the inverse effective resistance from node i to the nodes already
// grounded, at most n bars of q >= q_min away).
//
// Formats:
//   D (input)  off-diagonal entries in `lower`, diagonal in `recip`: Q16.16 q
//   L          Q2.30
//   pivots     kept as a normalised reciprocal 1/d_i = recip[i] * 2^-(62 + shift[i]),
//              recip[i] in [2^30, 2^31]: 31 significant bits over d's whole range
//   b (solve)  Q.36 force (q Q16.16 x Len Q12.20, exact products)
//   x (solve)  Q.40 length (rig units)
//
// LayerError: the factor entries carry a relative error of about 2^-30 each and
// every product in the solve is rounded once at 2^-36 (force) or 2^-40
// (length); with |L| <= 1 the solution's error is a relative one of the
// order of kappa(D) * 2^-29 in norm (far less per component for these
// diagonally dominant M-matrices) plus (n + profile) * 2^-40 rig units. The
// bar-net step solves for the nodes' move from their skinned positions (the
// loads alone on the right), so the error scales with the move, not with
// the positions; tests/sim_core/barnet measures it against a double solve of eq. (4)
// (within 2^-12 of a Len LSB before the final rounding on every net there).
#pragma once

#include <cstdint>
#include <span>

#include "sim_core/fixed/scalar.hpp"
#include "vector_kernel.hpp"

namespace sinew::barnet {

struct SkylineFactor {
  uint32_t n = 0;
  std::span<uint32_t> first;   // n
  std::span<uint32_t> offset;  // n + 1
  std::span<int32_t> lower;    // offset[n] entries
  std::span<int64_t> recip;    // n
  std::span<int32_t> shift;    // n
};

// Smallest pivot accepted (Q.32 raw): 2^-24 of a q unit, far below the
// smallest legitimate pivot q_min / n_max = 2^-18 and far above rounding
// noise; a smaller pivot means a singular net.
inline constexpr int64_t kMinPivotQ32 = int64_t{1} << 8;

// Factorises in place. On entry `lower` holds D's off-diagonal entries and
// `recip` its diagonal (Q16.16 raw); `row` is scratch of n entries. Returns
// the first row whose pivot is below kMinPivotQ32, or n if D is positive
// definite.
uint32_t ldlt_factor(const SkylineFactor& f, std::span<int64_t> row);

// Solves L D L^T x = b in place: v holds b (Q.36) on entry and x (Q.40) on
// exit. Saturates (counting) if a value would leave +-2^61.
void ldlt_solve(const SkylineFactor& f, std::span<int64_t> v, fx::Saturation& sat);

// The three axes of eq. (4) at once, x, y and z of node i at v[3 i + c]:
// each axis gets exactly ldlt_solve's words and the count is the three
// solves' total, with one pass over the factor instead of three. `kernel`
// picks who sweeps a factor with every |L_ij| <= 1 (the same words either way).
void ldlt_solve_axes(const SkylineFactor& f, std::span<int64_t> v, fx::Saturation& sat, VectorKernel kernel);

#if defined(__x86_64__)
namespace detail {
// The AVX2 sweeps (ldlt_skyline_avx2.cpp), for |L_ij| <= 2^30 and a CPU
// with AVX2: the forward and backward passes of ldlt_solve_axes, word for word.
void solve_forward_unit_avx2(const SkylineFactor& f, int64_t* x, fx::Saturation& sat);
void solve_backward_unit_avx2(const SkylineFactor& f, int64_t* x, fx::Saturation& sat);
}  // namespace detail
#endif

}  // namespace sinew::barnet
