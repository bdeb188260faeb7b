// Eq. (4) of barnet-driven-skinning's appendix in double, written from the
// appendix alone: the branch-node matrix C_s of eq. (1), split into its free
// and fixed columns C and C_f, D = C^t Q C and D_f = C^t Q C_f (eq. (3)),
// the nodes partitioned by their kind only. Shared by the oracle tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "host_tools/layers/common/dense_solve.hpp"
#include "sim_core/barnet/barnet.hpp"

namespace sinew::test::barnet {

namespace bn = sinew::barnet;

// Dense double matrices, row-major.
struct PaperSystem {
  uint32_t free_count = 0, fixed_count = 0;
  std::vector<uint32_t> free_nodes, fixed_nodes;  // model node indices, in node order
  std::vector<double> d, d_f;                     // n x n, n x n_f
};

// C_s(j, i) = +1 at one extremity of bar j, -1 at the other (eq. (1));
// D = C^t Q C, D_f = C^t Q C_f, formed as the products they are. q: the
// bars' force densities (Q16.16 values; empty: the model's) times q_scale.
inline PaperSystem paper_system(const bn::BarnetModel& m, double q_scale = 1.0,
                                const std::vector<double>& q_bars = {}) {
  PaperSystem s;
  std::vector<int> column(m.nodes.size(), -1);
  std::vector<bool> fixed(m.nodes.size(), false);
  for (uint32_t i = 0; i < m.nodes.size(); ++i) {
    fixed[i] = m.nodes[i].kind == static_cast<uint8_t>(bn::NodeKind::kFixed);
    column[i] = static_cast<int>(fixed[i] ? s.fixed_nodes.size() : s.free_nodes.size());
    (fixed[i] ? s.fixed_nodes : s.free_nodes).push_back(i);
  }
  s.free_count = static_cast<uint32_t>(s.free_nodes.size());
  s.fixed_count = static_cast<uint32_t>(s.fixed_nodes.size());
  const size_t bars = m.bars.size();
  std::vector<double> c(bars * s.free_count, 0), cf(bars * s.fixed_count, 0), q(bars, 0);
  for (size_t j = 0; j < bars; ++j) {
    const bn::BarRecord& b = m.bars[j];
    q[j] = std::ldexp(q_bars.empty() ? static_cast<double>(b.q) : q_bars[j], -16) * q_scale;
    const uint32_t ends[2] = {b.a, b.b};
    const double sign[2] = {+1.0, -1.0};
    for (int e = 0; e < 2; ++e) {
      const uint32_t i = ends[e];
      if (fixed[i])
        cf[j * s.fixed_count + static_cast<size_t>(column[i])] = sign[e];
      else
        c[j * s.free_count + static_cast<size_t>(column[i])] = sign[e];
    }
  }
  s.d.assign(size_t{s.free_count} * s.free_count, 0);
  s.d_f.assign(size_t{s.free_count} * s.fixed_count, 0);
  for (size_t j = 0; j < bars; ++j)
    for (uint32_t r = 0; r < s.free_count; ++r) {
      const double crq = c[j * s.free_count + r] * q[j];
      if (crq == 0) continue;
      for (uint32_t k = 0; k < s.free_count; ++k) s.d[r * s.free_count + k] += crq * c[j * s.free_count + k];
      for (uint32_t k = 0; k < s.fixed_count; ++k) s.d_f[r * s.fixed_count + k] += crq * cf[j * s.fixed_count + k];
    }
  return s;
}

// Solves D x = b (D is SPD): Gaussian elimination with partial pivoting.
inline std::vector<double> paper_solve(std::vector<double> a, std::vector<double> b) {
  return layers::solve_dense(std::move(a), std::move(b));
}

// Largest row sum of D^-1 (D is an M-matrix, so D^-1 >= 0 and this is its
// infinity norm): a load error of e per free node moves a free node by at
// most this x e.
inline double paper_inverse_norm(const PaperSystem& s) {
  const std::vector<double> x = paper_solve(s.d, std::vector<double>(s.free_count, 1.0));
  double largest = 0;
  for (double v : x) largest = std::max(largest, std::abs(v));
  return largest;
}

}  // namespace sinew::test::barnet
