#include "wrap.hpp"

#include "sim_core/fixed/rsqrt_fast.hpp"

namespace sinew::barnet::detail {
namespace {

int32_t component(fx::Vec3 v, size_t c) { return c == 0 ? v.x : (c == 1 ? v.y : v.z); }

void wrap_saturating(const BarnetModel& m, std::span<const TriangleFrame> frames, const std::span<fx::Len> (&skin)[3],
                     fx::Saturation& sat) {
  constexpr int64_t kAccLimit = int64_t{1} << 62;
  for (uint32_t w = 0; w < m.wrap.size(); ++w) {
    const WrapRecord& r = m.wrap[w];
    const TriangleFrame& f = frames[r.triangle];
    for (size_t c = 0; c < 3; ++c) {
      int64_t acc = int64_t{r.offset} * component(f.normal, c);
      for (uint32_t k = 0; k < 3; ++k) acc = fx::add_sat_i64(acc, int64_t{r.bary[k]} * component(f.corner[k], c));
      skin[c][w] = fx::sat_i32(fx::round_shift(fx::clamp_i64(acc, -kAccLimit, kAccLimit), 30), sat);
    }
  }
}

// The same words when every record has |b0| + |b1| + |b2| <= 2^31 and |d|
// <= 2^30: then |sum_k b_k c_k| <= 2^62 and |d n_c| <= 2^61, so every
// partial sum stays below 2^63 without saturating; and where the sum passes
// the +-2^62 clamp, the clamped and the unclamped value both round beyond
// int32 and saturate alike.
void wrap_plain(const BarnetModel& m, std::span<const TriangleFrame> frames, const std::span<fx::Len> (&skin)[3],
                fx::Saturation& sat) {
  for (uint32_t w = 0; w < m.wrap.size(); ++w) {
    const WrapRecord& r = m.wrap[w];
    const TriangleFrame& f = frames[r.triangle];
    const int64_t b0 = r.bary[0], b1 = r.bary[1], b2 = r.bary[2], d = r.offset;
    const int64_t x = d * f.normal.x + b0 * f.corner[0].x + b1 * f.corner[1].x + b2 * f.corner[2].x;
    const int64_t y = d * f.normal.y + b0 * f.corner[0].y + b1 * f.corner[1].y + b2 * f.corner[2].y;
    const int64_t z = d * f.normal.z + b0 * f.corner[0].z + b1 * f.corner[1].z + b2 * f.corner[2].z;
    // Round half up as (v + 2^29) >> 30 (|v| < 2^63 - 2^29 here: no
    // overflow, round_shift's value); one range test for the three.
    const int64_t rx = (x + (int64_t{1} << 29)) >> 30, ry = (y + (int64_t{1} << 29)) >> 30,
                  rz = (z + (int64_t{1} << 29)) >> 30;
    const auto outside = [](int64_t v) { return static_cast<uint64_t>(v - INT32_MIN) >> 32; };
    if ((outside(rx) | outside(ry) | outside(rz)) == 0) {
      skin[0][w] = static_cast<int32_t>(rx);
      skin[1][w] = static_cast<int32_t>(ry);
      skin[2][w] = static_cast<int32_t>(rz);
    } else {
      skin[0][w] = fx::sat_i32(rx, sat);
      skin[1][w] = fx::sat_i32(ry, sat);
      skin[2][w] = fx::sat_i32(rz, sat);
    }
  }
}

}  // namespace

fx::Vec3 triangle_normal(fx::Vec3 a, fx::Vec3 b, fx::Vec3 c) {
  fx::Vec3 unit{0, 0, 0};
  fx::normalize_fast(shifted_cross(a, b, c), &unit);  // degenerate triangle: zero normal, offset ignored
  return unit;
}

void make_triangle_frames(const BarnetModel& m, const std::span<fx::Len> (&node)[3], std::span<TriangleFrame> frames,
                          VectorKernel kernel) {
#if defined(__x86_64__)
  if (kernel == VectorKernel::kAvx512 && vector_kernel_supported(VectorKernel::kAvx512) &&
      make_triangle_frames_avx512(m, node, frames))
    return;
  if (runs_avx2_loops(kernel) && vector_kernel_supported(VectorKernel::kAvx2))
    return make_triangle_frames_avx2(m, node, frames);
#endif
  (void)kernel;
  for (uint32_t t = 0; t < m.triangles.size(); ++t) {
    const ControlTriangle& tri = m.triangles[t];
    TriangleFrame& f = frames[t];
    fx::Vec3 corner[3];  // locals: narrow stores to the frame would not forward to wide reloads
    for (uint32_t k = 0; k < 3; ++k) corner[k] = {node[0][tri.node[k]], node[1][tri.node[k]], node[2][tri.node[k]]};
    for (uint32_t k = 0; k < 3; ++k) f.corner[k] = corner[k];
    f.normal = triangle_normal(corner[0], corner[1], corner[2]);
    f.pad = 0;
  }
}

void wrap_vertices(const BarnetModel& m, std::span<const TriangleFrame> frames, bool bounded,
                   const std::span<fx::Len> (&skin)[3], fx::Saturation& sat, VectorKernel kernel) {
  if (!bounded) return wrap_saturating(m, frames, skin, sat);
#if defined(__x86_64__)
  if (runs_avx2_loops(kernel) && vector_kernel_supported(VectorKernel::kAvx2) && wrap_bounded_avx2(m, frames, skin))
    return;
#endif
  (void)kernel;
  wrap_plain(m, frames, skin, sat);
}

}  // namespace sinew::barnet::detail
