#include "trilinear_inverse.hpp"

#include <cmath>

namespace sinew::anatomy_build {
namespace {

P3 sub(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double det3(const P3& a, const P3& b, const P3& c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - b[0] * (a[1] * c[2] - a[2] * c[1]) + c[0] * (a[1] * b[2] - a[2] * b[1]);
}

struct Slice {
  P3 c00, e1, e2, e3;  // B(s, t) = c00 + s e1 + t e2 + s t e3
};

Slice slice_of(const P3* q) {
  Slice s;
  s.c00 = q[0];
  s.e1 = sub(q[1], q[0]);
  s.e2 = sub(q[3], q[0]);
  for (int c = 0; c < 3; ++c)
    s.e3[static_cast<size_t>(c)] = q[2][static_cast<size_t>(c)] - q[1][static_cast<size_t>(c)] -
                                   q[3][static_cast<size_t>(c)] + q[0][static_cast<size_t>(c)];
  return s;
}

P3 bilinear(const Slice& s, double a, double b) {
  P3 r;
  for (size_t c = 0; c < 3; ++c) r[c] = s.c00[c] + a * s.e1[c] + b * s.e2[c] + a * b * s.e3[c];
  return r;
}

}  // namespace

P3 trilinear_forward(const P3 corners[8], const P3& stu) {
  const Slice s0 = slice_of(corners), s1 = slice_of(corners + 4);
  const P3 b0 = bilinear(s0, stu[0], stu[1]), b1 = bilinear(s1, stu[0], stu[1]);
  P3 r;
  for (size_t c = 0; c < 3; ++c) r[c] = b0[c] + stu[2] * (b1[c] - b0[c]);
  return r;
}

bool trilinear_inverse(const P3 corners[8], const P3& target, P3* stu, double* residual) {
  const Slice s0 = slice_of(corners), s1 = slice_of(corners + 4);
  P3 x{0.5, 0.5, 0.5};
  double res = 0;
  for (int it = 0; it < 32; ++it) {
    const double s = x[0], t = x[1], u = x[2];
    const P3 b0 = bilinear(s0, s, t), b1 = bilinear(s1, s, t);
    P3 f, ds, dt, du;
    for (size_t c = 0; c < 3; ++c) {
      f[c] = b0[c] + u * (b1[c] - b0[c]) - target[c];
      ds[c] = (1 - u) * (s0.e1[c] + t * s0.e3[c]) + u * (s1.e1[c] + t * s1.e3[c]);
      dt[c] = (1 - u) * (s0.e2[c] + s * s0.e3[c]) + u * (s1.e2[c] + s * s1.e3[c]);
      du[c] = b1[c] - b0[c];
    }
    res = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    const double d = det3(ds, dt, du);
    if (!(std::fabs(d) > 0)) return false;
    // Cramer's rule for J delta = -f.
    const P3 nf{-f[0], -f[1], -f[2]};
    const P3 delta{det3(nf, dt, du) / d, det3(ds, nf, du) / d, det3(ds, dt, nf) / d};
    for (size_t c = 0; c < 3; ++c) x[c] += delta[c];
    if (std::fabs(delta[0]) + std::fabs(delta[1]) + std::fabs(delta[2]) < 1e-14) break;
  }
  const P3 p = trilinear_forward(corners, x);
  const P3 f = sub(p, target);
  res = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  *stu = x;
  *residual = res;
  return true;
}

}  // namespace sinew::anatomy_build
