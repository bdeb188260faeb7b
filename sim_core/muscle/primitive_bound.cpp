#include "primitive_bound.hpp"

#include "primitive_deform.hpp"
#include "sim_core/fixed/wide.hpp"

namespace sinew::muscle {

bool near_orthonormal(const fx::Vec3 axis[3]) {
  constexpr int64_t kLimit = (int64_t{1} << 30) + (int64_t{1} << 20);  // components of a unit vector, with slack
  constexpr int64_t kOne2 = int64_t{1} << 60, kSlack = int64_t{1} << 44;
  for (int i = 0; i < 3; ++i)
    for (int32_t c : {axis[i].x, axis[i].y, axis[i].z})
      if (c > kLimit || c < -kLimit) return false;
  // |products| < 3 * 2^61: every sum fits in int64.
  const auto dot = [](fx::Vec3 a, fx::Vec3 b) { return int64_t{a.x} * b.x + int64_t{a.y} * b.y + int64_t{a.z} * b.z; };
  for (int i = 0; i < 3; ++i) {
    const int64_t self = dot(axis[i], axis[i]) - kOne2;
    if (self > kSlack || self < -kSlack) return false;
    const int64_t cross = dot(axis[i], axis[(i + 1) % 3]);
    if (cross > kSlack || cross < -kSlack) return false;
  }
  return true;
}

PrimitiveBound primitive_bound(const PrimitiveFrame& f) {
  PrimitiveBound b;
  if (f.active == 0 || is_deformed(f.deformation) || !near_orthonormal(f.axis)) return b;
  for (int i = 0; i < 3; ++i)
    if (f.extent[i] <= 0) return b;
  constexpr uint64_t kInverseSlack = uint64_t{1} << 16;  // 2^-14 in Q2.30
  for (int w = 0; w < 3; ++w) {
    uint64_t sum = 0;
    for (int i = 0; i < 3; ++i) {
      const int32_t a = w == 0 ? f.axis[i].x : (w == 1 ? f.axis[i].y : f.axis[i].z);
      // (|a| + 2^16) < 2^31 (near_orthonormal: |a| <= 2^30 + 2^20) and 2 e + 1 < 2^32: the product fits.
      const uint64_t product = (fx::magnitude(a) + kInverseSlack) * (2 * static_cast<uint64_t>(f.extent[i]) + 1);
      sum += (product + (uint64_t{1} << 31) - 1) >> 31;  // (|a| + 2^-14)(e + 1/2) in Len, rounded up
    }
    b.half[w] = sum;
  }
  uint64_t reach = 0;
  for (int i = 0; i < 3; ++i) {
    const uint64_t e = static_cast<uint64_t>(f.extent[i]) + 1;  // <= 2^31
    reach += e * e;                                             // < 3 * 2^62
  }
  if (reach > (uint64_t{1} << 63) - 1) return b;  // twice it would not fit
  b.reach2 = 2 * reach;
  b.usable = true;
  b.centre = f.centre;
  return b;
}

}  // namespace sinew::muscle
