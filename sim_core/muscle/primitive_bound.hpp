// A cull for the inside tests of the implicit primitives (LEMAN §6.11: every
// fat point is tested against every primitive, each relaxation round): a
// world-axis box about a primitive's centre outside which every point is
// outside the primitive's own bounding box as primitive_sample computes it
// (local coordinates l_i = a_i . d rounded to the LSB, outside when |l_i| >=
// e_i). primitive_sample, primitive_value and primitive_push_out then leave
// the point as it is, so a pass that skips such points computes the same
// words as one that tests them all.
//
// Why the box holds: with the axes' rows a_i of A within 2^-16 of unit
// length and |a_i . a_j| <= 2^-16 (near-orthonormal), A A^T = I + E with row
// sums of |E| <= 3 2^-16, so each entry of A^-1 = A^T (I + E)^-1 is within
// 2^-14 of A^T's. A point whose rounded l_i are all inside has exact |l_i| <
// e_i + 1/2, hence |d_w| = |sum_i (A^-1)_wi l_i| < sum_i (|a_iw| + 2^-14)
// (e_i + 1/2): half[w], rounded up. A sphere about the centre would take in
// far more of a long muscle's surroundings than this box.
#pragma once

#include <cstdint>

#include "muscle_state.hpp"
#include "sim_core/fixed/vec3.hpp"
#include "sim_core/fixed/wide.hpp"

namespace sinew::muscle {

struct PrimitiveBound {
  bool usable = false;  // false: no cull (inactive, deformed, or axes not near-orthonormal)
  fx::Vec3 centre{0, 0, 0};
  uint64_t half[3] = {0, 0, 0};  // world-axis half-widths, Len
  // The wider reach of a list that must hold every point that may come
  // inside while its members alone are moved (the dynamic skin's reaction
  // candidates): twice the squared radius that holds the primitive's box,
  // 2 sum (e_i + 1)^2 (Len^2). With |a_i|^2 within 2^-16 of 1 and |a_i .
  // a_j| <= 2^-16, sum (a_i . d)^2 >= (1 - 3 2^-16) |d|^2 (Gershgorin), so a
  // point inside the box has |d|^2 < sum (e_i + 1)^2 / (1 - 3 2^-16).
  uint64_t reach2 = 0;
};

// Axes within 2^-16 of orthonormal (as above), components within 2^-10 of
// a unit vector's range.
bool near_orthonormal(const fx::Vec3 axis[3]);

// The bound of an active, undeformed primitive with near-orthonormal axes;
// otherwise one that is not usable. (Barr's deformations move the surface
// beyond the undeformed box.)
PrimitiveBound primitive_bound(const PrimitiveFrame& f);

// p is certainly outside the primitive the bound was made from. Branch-free.
inline bool beyond_bound(const PrimitiveBound& b, fx::Vec3 p) {
  const fx::Vec3 d = fx::sub(p, b.centre);  // saturated, as primitive_sample forms it
  // Unsigned ors of the three tests, not a chain of branches.
  const unsigned beyond = static_cast<unsigned>(fx::magnitude(d.x) >= b.half[0]) |
                          static_cast<unsigned>(fx::magnitude(d.y) >= b.half[1]) |
                          static_cast<unsigned>(fx::magnitude(d.z) >= b.half[2]);
  return (static_cast<unsigned>(b.usable) & beyond) != 0;
}

// p is beyond the wider reach2: outside the primitive with room to spare.
inline bool beyond_reach(const PrimitiveBound& b, fx::Vec3 p) {
  const fx::Vec3 d = fx::sub(p, b.centre);
  const uint64_t x = fx::magnitude(d.x), y = fx::magnitude(d.y), z = fx::magnitude(d.z);
  return b.usable && x * x + y * y + z * z >= b.reach2;  // each square <= 2^62: the sum < 2^64
}

}  // namespace sinew::muscle
