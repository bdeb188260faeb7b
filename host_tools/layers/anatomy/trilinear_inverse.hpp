// Inverse of the parametric trilinear (tri-affine) map of a muscle cell
// (anatomically-based-modeling §5.1, Figure 6) by 3D Newton-Raphson, in
// double (+ - * / only: identical on every platform).
#pragma once

#include <array>

namespace sinew::anatomy_build {

using P3 = std::array<double, 3>;

// corners: c00, c10, c11, c01 of the u = 0 slice, then the same of u = 1.
P3 trilinear_forward(const P3 corners[8], const P3& stu);

// Solves trilinear_forward(corners, stu) = target from stu = (0.5, 0.5,
// 0.5), at most 32 iterations. Returns false for a singular Jacobian;
// *residual is the final |P(stu) - target|.
bool trilinear_inverse(const P3 corners[8], const P3& target, P3* stu, double* residual);

}  // namespace sinew::anatomy_build
