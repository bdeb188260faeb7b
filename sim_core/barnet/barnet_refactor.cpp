#include "barnet_refactor.hpp"

namespace sinew::barnet {

void scale_force_densities(const BarnetModel& m, std::span<const int32_t> external, std::span<ForceDensity> q_out,
                           fx::Saturation& sat) {
  for (size_t b = 0; b < m.bars.size(); ++b) q_out[b] = m.bars[b].q;
  for (const ForceDensityInput& r : m.q_inputs) {
    int32_t v = r.input < external.size() ? external[r.input] : kForceDensityOne;
    // A scale of 0 or below means nothing physically (no bar); it is what an
    // input never fed reads, so it leaves the compiled q rather than the softest.
    if (v <= 0) v = kForceDensityOne;
    const int64_t scale = fx::clamp_i64(v, kMinForceDensityScale, kMaxForceDensityScale);
    for (uint32_t b = r.first_bar; b < r.first_bar + r.bar_count; ++b) {
      // q (<= 2^24) x scale (<= 2^24) < 2^48: exact, then rounded once.
      const int64_t q = fx::round_shift(int64_t{q_out[b]} * scale, kForceDensityFracBits);
      const int64_t clamped = fx::clamp_i64(q, kMinForceDensity, kMaxForceDensity);
      sat.events += static_cast<uint32_t>(clamped != q);
      q_out[b] = static_cast<ForceDensity>(clamped);
    }
  }
}

void assemble_matrix(std::span<const BarRecord> bars, std::span<const ForceDensity> q, const SkylineFactor& f) {
  // D_ii = sum of q on node i's bars, D_ij = -sum of q on bars between free
  // nodes i and j (eq. (3)); Q16.16. At most 16 bars of q <= 256 per node.
  const uint32_t free = f.n;
  for (int32_t& v : f.lower) v = 0;
  for (int64_t& v : f.recip) v = 0;
  for (size_t k = 0; k < bars.size(); ++k) {
    const BarRecord& b = bars[k];
    if (b.a < free) f.recip[b.a] += q[k];
    if (b.b < free) f.recip[b.b] += q[k];
    if (b.a < free && b.b < free) {
      const uint32_t hi = b.a > b.b ? b.a : b.b, lo = b.a > b.b ? b.b : b.a;
      f.lower[f.offset[hi] + (lo - f.first[hi])] -= q[k];
    }
  }
}

uint64_t refactor_products(const SkylineFactor& f) {
  uint64_t products = 0;
  for (uint32_t i = 0; i < f.n; ++i) {
    const uint32_t fi = f.first[i];
    for (uint32_t j = fi; j < i; ++j) {
      const uint32_t start = fi > f.first[j] ? fi : f.first[j];
      products += j - start;  // g_ij's inner product
    }
    products += 2 * uint64_t{i - fi};  // L_ij = g_ij / d_j and d_i's sum
  }
  return products;
}

}  // namespace sinew::barnet
