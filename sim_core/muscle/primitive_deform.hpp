// Barr's global deformations of the implicit primitives (LEMAN §5.2, §6.11;
// [Barr 84]): taper, twist and bend about the primitive's local Z axis, the
// parameters and ranges in muscle_model.hpp (PrimitiveDeformation).
//
// Local coordinates are Len (Q12.20) in int64, in the primitive's frame.
// The chain, undeformed p0 -> taper -> p1 -> twist -> p2 -> bend -> p3:
//   taper: x1 = r x0, y1 = r y0, r = 1 + taper z / c
//   twist: (x2, y2) = rot(theta) (x1, y1), theta = twist z / c
//   bend:  zh = clamp(z, -c, c), theta = bend zh / c, R = c / beta,
//          x3 = R + cos(theta) (x2 - R) + sin(theta) (z - zh)
//          z3 = -sin(theta) (x2 - R) + cos(theta) (z - zh)
// (Barr's bend of the Y axis towards Z, relabelled: the Z axis bends
// towards +X.) The inside test (§6.11) maps a point back, p0 = D^-1(p3),
// and tests F(p0) < 1; the gradient of F o D^-1 is the covariant transform
// J^T grad F (J = dp0/dp3), computed analytically per stage.
#pragma once

#include <cstdint>

#include "muscle_state.hpp"
#include "sim_core/fixed/trig.hpp"

namespace sinew::muscle {

inline bool is_deformed(const PrimitiveDeformation& d) { return d.taper != 0 || d.twist != 0 || d.bend != 0; }

// Signed bend radius R = c / beta (Len, the sign of bend): c up to 2^31
// and |bend| >= 1 give |R| < 2^62.
int64_t bend_radius(int64_t half_height, int64_t bend);

// Intermediates of the inverse map the gradient needs.
struct DeformTrace {
  int64_t undeformed[3] = {};  // p0
  int64_t tapered[3] = {};     // p1
  int64_t unbent_x = 0;        // x2
  fx::Unit taper_r = fx::kUnitOne;
  fx::SinCos twist{0, fx::kUnitOne};
  fx::SinCos bend{0, fx::kUnitOne};
};

// p3 -> p0 (trace->undeformed). False when the point is certainly outside
// the primitive (|z| >= c, or x1, y1 beyond twice the extents: r <= 3/2),
// the trace then partial. For bent primitives points beyond the bend's
// centre (x2 on the far side of R) have no exact inverse; they map outside.
bool primitive_undeform(const PrimitiveFrame& f, const int64_t local[3], DeformTrace* trace);

// p0 -> p3. Beyond the caps (|z| > c) taper and twist keep their cap
// values, so the map stays one to one there (points outside stay outside).
void primitive_deform(const PrimitiveFrame& f, const int64_t in[3], int64_t out[3]);

// Turns the undeformed gradient g (any scale, each |g_i| < 2^62) at
// trace->undeformed into a vector along the deformed gradient at p3 (a
// positive multiple of J^T g), each component below 2^30.
void primitive_deform_gradient(const PrimitiveFrame& f, const DeformTrace& trace, int64_t g[3]);

// Scales g down by a power of two until every |g_i| < 2^30 (direction kept).
void narrow_direction(int64_t g[3]);

}  // namespace sinew::muscle
