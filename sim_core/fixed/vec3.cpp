#include "vec3.hpp"

#include "norm.hpp"
#include "rsqrt_fast.hpp"
#include "sqrt.hpp"
#include "wide.hpp"

namespace sinew::fx {

bool normalize_to_unit(Vec3 v, Vec3* out) {
  const int32_t c[3] = {v.x, v.y, v.z};
  const NormDivisor d = norm_divisor(c, 3);
  *out = {divide_by_norm(v.x, d), divide_by_norm(v.y, d), divide_by_norm(v.z, d)};
  return d.length != 0;
}

uint32_t length(Vec3 v) {
  const uint64_t x = magnitude(v.x), y = magnitude(v.y), z = magnitude(v.z);
  const uint64_t n2 = x * x + y * y + z * z;  // < 3 * 2^62 < 2^64
  return isqrt_fast(n2);
}

}  // namespace sinew::fx
