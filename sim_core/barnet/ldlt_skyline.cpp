#include "ldlt_skyline.hpp"

#include "wide_sat.hpp"

namespace sinew::barnet {
namespace {

int bit_length(uint64_t v) {
  int n = 0;
  while (v != 0) {
    ++n;
    v >>= 1;
  }
  return n;
}

// 1/d as m * 2^-(62 + e), m in [2^30, 2^31], for d > 0 (Q.32 raw).
void reciprocal(int64_t d, int64_t* m, int32_t* e) {
  const int bits = bit_length(static_cast<uint64_t>(d));
  int32_t shift = bits - 32;  // d = dn * 2^shift, dn in [2^31, 2^32)
  int64_t dn = shift > 0 ? fx::round_shift(d, shift) : d << -shift;
  if (dn >= (int64_t{1} << 32)) {  // rounding carried into the next bit
    dn >>= 1;
    ++shift;
  }
  // round(2^62 / dn), half up, in unsigned arithmetic (2^62 itself is the
  // numerator, beyond div_round's precondition).
  const uint64_t num = uint64_t{1} << 62, den = static_cast<uint64_t>(dn);
  const uint64_t quotient = num / den, remainder = num % den;
  *m = static_cast<int64_t>(quotient + (2 * remainder >= den ? 1u : 0u));
  *e = shift;
}

}  // namespace

uint32_t ldlt_factor(const SkylineFactor& f, std::span<int64_t> row) {
  fx::Saturation sat;
  for (uint32_t i = 0; i < f.n; ++i) {
    const uint32_t fi = f.first[i];
    int32_t* li = f.lower.data() + f.offset[i];
    // g_ij = D_ij - sum_k L_jk g_ik (g_ij = L_ij d_j), Q.32.
    for (uint32_t j = fi; j < i; ++j) {
      int64_t g = int64_t{li[j - fi]} << 16;
      const uint32_t fj = f.first[j];
      const int32_t* lj = f.lower.data() + f.offset[j];
      for (uint32_t k = fi > fj ? fi : fj; k < j; ++k)
        g = fx::add_sat_i64(g, -mul_l30_round_sat(lj[k - fj], row[k], sat));
      row[j] = clamp_vector(g, sat);
    }
    // d_i = D_ii - sum_k L_ik g_ik, then L_ij = g_ij / d_j.
    int64_t d = f.recip[i] << 16;
    for (uint32_t j = fi; j < i; ++j) {
      const int64_t l = mul_shift_round_sat(row[j], f.recip[j], 32 + f.shift[j], sat);
      li[j - fi] = fx::sat_i32(l);
      d = fx::add_sat_i64(d, -mul_l30_round_sat(li[j - fi], row[j], sat));
    }
    if (d < kMinPivotQ32) return i;
    reciprocal(d, &f.recip[i], &f.shift[i]);
  }
  return f.n;
}

void ldlt_solve(const SkylineFactor& f, std::span<int64_t> v, fx::Saturation& total) {
  // Counted locally: the compiler cannot prove the caller's count aliases
  // no element of v, and would store it back after every product.
  fx::Saturation sat;
  // Forward: L y = b.
  for (uint32_t i = 0; i < f.n; ++i) {
    const uint32_t fi = f.first[i];
    const int32_t* li = f.lower.data() + f.offset[i];
    int64_t y = v[i];
    for (uint32_t j = fi; j < i; ++j) y = fx::add_sat_i64(y, -mul_l30_round_sat(li[j - fi], v[j], sat));
    v[i] = clamp_vector(y, sat);
  }
  // Diagonal: z = y / d, force Q.36 -> length Q.40: z = y * 2^4 / d_q32.
  for (uint32_t i = 0; i < f.n; ++i) v[i] = mul_shift_round_sat(v[i], f.recip[i], 26 + f.shift[i], sat);
  // Backward: L^T x = z, row by row from the last (column sweeps of L^T).
  for (uint32_t i = f.n; i-- > 0;) {
    const uint32_t fi = f.first[i];
    const int32_t* li = f.lower.data() + f.offset[i];
    const int64_t xi = v[i];
    for (uint32_t j = fi; j < i; ++j) v[j] = clamp_vector(v[j] - mul_l30_round_sat(li[j - fi], xi, sat), sat);
  }
  total.events += sat.events;
}

namespace {

template <bool kUnitBounded>
inline int64_t l30_product(int32_t l, int64_t v, fx::Saturation& sat) {
  if constexpr (kUnitBounded) {
    return mul_l30_unit_bounded(l, v);
  } else {
    return mul_l30_round_sat(l, v, sat);
  }
}

// Forward: L y = b, the three axes' sums side by side in the same order.
template <bool kUnitBounded>
void solve_forward(const SkylineFactor& f, int64_t* x, fx::Saturation& sat) {
  for (uint32_t i = 0; i < f.n; ++i) {
    const uint32_t fi = f.first[i];
    const int32_t* li = f.lower.data() + f.offset[i];
    int64_t y[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    for (uint32_t j = fi; j < i; ++j) {
      const int32_t l = li[j - fi];
      for (uint32_t c = 0; c < 3; ++c) y[c] = fx::add_sat_i64(y[c], -l30_product<kUnitBounded>(l, x[3 * j + c], sat));
    }
    for (uint32_t c = 0; c < 3; ++c) x[3 * i + c] = clamp_vector(y[c], sat);
  }
}

// Diagonal, force Q.36 -> length Q.40.
void solve_diagonal(const SkylineFactor& f, int64_t* x, fx::Saturation& sat) {
  for (uint32_t i = 0; i < f.n; ++i)
    for (uint32_t c = 0; c < 3; ++c) x[3 * i + c] = mul_shift_round_sat(x[3 * i + c], f.recip[i], 26 + f.shift[i], sat);
}

// Backward: L^T x = z.
template <bool kUnitBounded>
void solve_backward(const SkylineFactor& f, int64_t* x, fx::Saturation& sat) {
  for (uint32_t i = f.n; i-- > 0;) {
    const uint32_t fi = f.first[i];
    const int32_t* li = f.lower.data() + f.offset[i];
    const int64_t xi[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    for (uint32_t j = fi; j < i; ++j) {
      const int32_t l = li[j - fi];
      for (uint32_t c = 0; c < 3; ++c)
        x[3 * j + c] = clamp_vector(x[3 * j + c] - l30_product<kUnitBounded>(l, xi[c], sat), sat);
    }
  }
}

}  // namespace

void ldlt_solve_axes(const SkylineFactor& f, std::span<int64_t> v, fx::Saturation& total, VectorKernel kernel) {
  // The factors of a net have |L_ij| <= 1 (the header's M-matrix argument);
  // one pass over L proves it for this factor, and its products then need
  // no clamp. Any other factor takes the clamping product: the same words.
  uint32_t beyond_unit = 0;
  for (const int32_t l : f.lower) beyond_unit |= static_cast<uint32_t>(l > fx::kUnitOne || l < -fx::kUnitOne);
  fx::Saturation sat;
  int64_t* const x = v.data();
  if (beyond_unit != 0) {
    solve_forward<false>(f, x, sat);
    solve_diagonal(f, x, sat);
    solve_backward<false>(f, x, sat);
  } else if (runs_avx2_loops(kernel) && vector_kernel_supported(VectorKernel::kAvx2)) {
#if defined(__x86_64__)
    detail::solve_forward_unit_avx2(f, x, sat);
    solve_diagonal(f, x, sat);
    detail::solve_backward_unit_avx2(f, x, sat);
#endif
  } else {
    solve_forward<true>(f, x, sat);
    solve_diagonal(f, x, sat);
    solve_backward<true>(f, x, sat);
  }
  total.events += sat.events;
}

}  // namespace sinew::barnet
