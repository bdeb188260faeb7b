// Primitive frames at the limits the runtime can produce: a muscle-attached
// primitive's extents follow the muscle (X, Y by the volume scale, Z by
// present / rest length, saturated), so its aspect ratio is not bounded by
// the validator's 64. Sampling and pushing out must stay defined (the
// sanitizer builds abort on signed overflow) and keep a unit normal.
#include <gtest/gtest.h>

#include <climits>

#include "sim_core/muscle/primitive.hpp"

namespace muscle = sinew::muscle;
namespace fx = sinew::fx;

namespace {

muscle::PrimitiveFrame frame(uint8_t kind, uint8_t exponent, fx::Len a, fx::Len b, fx::Len c) {
  muscle::PrimitiveFrame f;
  f.kind = kind;
  f.exponent = exponent;
  f.active = 1;
  f.axis[0] = {fx::kUnitOne, 0, 0};
  f.axis[1] = {0, fx::kUnitOne, 0};
  f.axis[2] = {0, 0, fx::kUnitOne};
  f.extent[0] = a;
  f.extent[1] = b;
  f.extent[2] = c;
  return f;
}

}  // namespace

TEST(PrimitiveExtremes, AspectRatiosBeyondTheValidatorsStayDefined) {
  const uint8_t kinds[][2] = {{0, 2}, {1, 2}, {2, 2}, {2, 4}, {2, 8}};
  const fx::Len extents[][3] = {{1, 1, INT32_MAX},
                                {INT32_MAX, 1, 1},
                                {1, INT32_MAX, INT32_MAX},
                                {INT32_MAX, INT32_MAX, INT32_MAX},
                                {1 << 10, 1 << 10, INT32_MAX},
                                {1 << 10, INT32_MAX, 64}};
  const fx::Vec3 points[] = {{0, 0, 0},           {0, 0, 1 << 30},
                             {0, 0, -(1 << 30)},  {0, 0, INT32_MAX - 1},
                             {1 << 9, 1 << 9, 0}, {-(1 << 9), 20, -(1 << 29)},
                             {31, -31, 1 << 20}};
  for (const auto& k : kinds)
    for (const auto& e : extents) {
      const muscle::PrimitiveFrame f = frame(k[0], k[1], e[0], e[1], e[2]);
      for (const fx::Vec3& p : points) {
        const muscle::PrimitiveSample s = muscle::primitive_sample(f, p);
        if (s.inside && !(s.normal == fx::Vec3{0, 0, 0})) {
          const int64_t n2 = fx::dot_wide(s.normal, s.normal);
          EXPECT_NEAR(static_cast<double>(n2) / 1152921504606846976.0, 1.0, 1e-6);
        }
        const fx::Vec3 out = muscle::primitive_push_out(f, p, {0, 0, fx::kUnitOne}, 8);
        (void)out;
      }
    }
}
