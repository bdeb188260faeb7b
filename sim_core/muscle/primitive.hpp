// Implicit muscle primitives (LEMAN §5.2, §6.11): fast inside tests with
// gradients, and the projection that moves a point out along the gradient.
//
// In the primitive's frame a point has local coordinates (x, y, z) and
// normalised ones q = (x/a, y/b, z/c), a, b, c its half-extents. The
// inside/outside function (Barr's superquadric, [Barr 81]):
//   sphere, superellipsoid p in {2, 4, 8}:  F = |qx|^p + |qy|^p + |qz|^p   (sphere: p = 2)
//   cylinder:                               F = qx^2 + qy^2, and |qz| < 1
// by exact integer powers, with the gradient dF/dx_i = p q_i^(p-1) / a_i;
//   general superellipsoid (exponent 0):    F = (|qx|^p_xy + |qy|^p_xy)^(p_z/p_xy) + |qz|^p_z
// in the log domain (superquadric.hpp). The point is inside when F < 1
// (§6.11); the gradient points out of the primitive. F is returned in Q2.30
// (values of 1 or more, including every point outside the bounding box,
// read as "outside").
//
// A primitive with a global deformation D (taper, twist, bend: §5.2,
// primitive_deform.hpp) is tested at D^-1(p): F and gradient_length are
// those of the undeformed point, `normal` the covariant J^T grad F.
#pragma once

#include <cstdint>

#include "muscle_state.hpp"

namespace sinew::muscle {

struct PrimitiveSample {
  bool inside = false;
  int64_t value = 0;            // F in Q2.30 (>= 2^30 outside); 2^32 for points outside the bounding box
  fx::Vec3 normal{0, 0, 0};     // unit outward gradient direction (world), Q2.30; zero at the centre
  fx::Len gradient_length = 0;  // |grad F| * max extent, Q12.20 (dimensionless, in Len format)
};

// Evaluates F and its gradient direction at `p` (Len, model space). Defined
// for any frame: the gradient's per-axis factor max extent / extent (Q16) is
// capped at 2^29 (aspect ratio 8192, far beyond a validated primitive's 64,
// reachable by a muscle-attached one stretched with its muscle), so its
// components stay below 2^62; beyond the cap the direction is approximate.
PrimitiveSample primitive_sample(const PrimitiveFrame& f, fx::Vec3 p);

// F alone (primitive_sample's value), without the gradient and normal where
// the point is outside: the inside tests of the reaction constraints.
int64_t primitive_value(const PrimitiveFrame& f, fx::Vec3 p);

// Moves p out of the primitive along the gradient: `newton_steps` Newton
// steps on G = F^(1/p) (p_z for the general superquadric) along the
// gradient (never more than the largest extent per step). `fallback` (a unit vector) is used at the centre,
// where the gradient vanishes. Returns the moved point (p if outside).
// Deformed primitives: the Newton steps run on the undeformed point, whose
// landing point is mapped forward (on the deformed surface, the move not
// exactly along the deformed gradient; primitive.cpp).
fx::Vec3 primitive_push_out(const PrimitiveFrame& f, fx::Vec3 p, fx::Vec3 fallback, int newton_steps);

}  // namespace sinew::muscle
