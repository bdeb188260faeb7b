// Single-precision counterparts of sim_core's fixed-point quaternion and
// affine operations, written as a float engine would: the baseline of
// fixed_ops_bench.cpp.
#pragma once

#include <cmath>

namespace sinew::bench {

struct Vec3F {
  float x, y, z;
};

struct QuatF {
  float w, x, y, z;
};

// Linear part row-major, then translation: p' = M p + t.
struct Mat34F {
  float m[3][3];
  float t[3];
};

// Hamilton product a * b (the convention of fx::mul).
inline QuatF mul(const QuatF& a, const QuatF& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

inline Vec3F transform_point(const Mat34F& a, Vec3F p) {
  return {a.m[0][0] * p.x + a.m[0][1] * p.y + a.m[0][2] * p.z + a.t[0],
          a.m[1][0] * p.x + a.m[1][1] * p.y + a.m[1][2] * p.z + a.t[1],
          a.m[2][0] * p.x + a.m[2][1] * p.y + a.m[2][2] * p.z + a.t[2]};
}

// As fx::normalize: the zero quaternion becomes identity.
inline bool normalize(QuatF* q) {
  const float n2 = q->w * q->w + q->x * q->x + q->y * q->y + q->z * q->z;
  if (n2 <= 0.0f) {
    *q = {1.0f, 0.0f, 0.0f, 0.0f};
    return false;
  }
  const float inv = 1.0f / std::sqrt(n2);
  *q = {q->w * inv, q->x * inv, q->y * inv, q->z * inv};
  return true;
}

}  // namespace sinew::bench
