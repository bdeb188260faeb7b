// A dense linear solve in double for the offline builders and the tests'
// oracles: Gaussian elimination with partial pivoting, + - * / only, so the
// same bits on every platform (with -ffp-contract=off). For small systems
// (tens to hundreds of unknowns).
#pragma once

#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace sinew::layers {

// Solves a x = b for a row-major n x n matrix a (taken by value: eliminated
// in place). a must be non-singular.
inline std::vector<double> solve_dense(std::vector<double> a, std::vector<double> b) {
  const size_t n = b.size();
  for (size_t k = 0; k < n; ++k) {
    size_t p = k;
    for (size_t i = k + 1; i < n; ++i)
      if (std::fabs(a[i * n + k]) > std::fabs(a[p * n + k])) p = i;
    if (p != k) {
      for (size_t j = 0; j < n; ++j) std::swap(a[k * n + j], a[p * n + j]);
      std::swap(b[k], b[p]);
    }
    for (size_t i = k + 1; i < n; ++i) {
      const double f = a[i * n + k] / a[k * n + k];
      if (f == 0) continue;
      for (size_t j = k; j < n; ++j) a[i * n + j] -= f * a[k * n + j];
      b[i] -= f * b[k];
    }
  }
  std::vector<double> x(n, 0);
  for (size_t i = n; i-- > 0;) {
    double v = b[i];
    for (size_t j = i + 1; j < n; ++j) v -= a[i * n + j] * x[j];
    x[i] = v / a[i * n + i];
  }
  return x;
}

}  // namespace sinew::layers
