// Step 4 of the bar-net step (barnet_step.hpp): the control triangles'
// frames (corners and unit normal), then every bound fine vertex, v =
// bary . (a, b, c) + offset * n. The scalar functions are the
// specification; the AVX2 kernels (wrap_avx2.cpp, x86-64 only, chosen when
// the CPU reports AVX2) write the same words for every input, and the
// kernel tests compare them word for word.
#pragma once

#include <bit>
#include <cstdint>
#include <span>

#include "barnet_state.hpp"
#include "barnet_step.hpp"
#include "sim_core/fixed/scalar.hpp"
#include "sim_core/fixed/vec3.hpp"
#include "sim_core/fixed/wide.hpp"

namespace sinew::barnet::detail {

// The exact int64 cross product e1 x e2, floor-shifted below
// 2^31: its direction is all the wrap uses, so it is normalised without a
// division (fx::normalize_fast: the direction exact to rounding, components
// within 2^-28 of the unit vector's). Inline: returned by a call, the Vec3
// comes back through narrow stores and a wide reload, which the CPU cannot
// forward.
[[gnu::always_inline]] inline fx::Vec3 shifted_cross_of_edges(fx::Vec3 e1, fx::Vec3 e2) {
  const int64_t n[3] = {int64_t{e1.y} * e2.z - int64_t{e1.z} * e2.y, int64_t{e1.z} * e2.x - int64_t{e1.x} * e2.z,
                        int64_t{e1.x} * e2.y - int64_t{e1.y} * e2.x};
  const uint64_t biggest = fx::magnitude(n[0]) | fx::magnitude(n[1]) | fx::magnitude(n[2]);
  const int shift = static_cast<int>(std::bit_width(biggest >> 31));  // then biggest >> shift < 2^31
  return {static_cast<int32_t>(n[0] >> shift), static_cast<int32_t>(n[1] >> shift),
          static_cast<int32_t>(n[2] >> shift)};
}
// The same for the triangle a, b, c: its edges b - a and c - a saturated
// to int32 (fx::sub).
[[gnu::always_inline]] inline fx::Vec3 shifted_cross(fx::Vec3 a, fx::Vec3 b, fx::Vec3 c) {
  return shifted_cross_of_edges(fx::sub(b, a), fx::sub(c, a));
}

// Unit normal (Q2.30) of the triangle a, b, c: shifted_cross through
// fx::normalize_fast; zero for a degenerate triangle.
fx::Vec3 triangle_normal(fx::Vec3 a, fx::Vec3 b, fx::Vec3 c);

// frames[t] for every control triangle t from the nodes' positions (every
// node count checked by the caller).
void make_triangle_frames(const BarnetModel& m, const std::span<fx::Len> (&node)[3], std::span<TriangleFrame> frames,
                          VectorKernel kernel);

// The wrap's definition: v_c = sat_i32(round((d n_c + sum_k b_k c_k) /
// 2^30)), the sum saturating in int64 and clamped to +-2^62 before the
// rounding. `bounded` (BarnetState::wrap_bounded) lets the plain sums stand
// in for the saturating ones; the kernel is used only then.
void wrap_vertices(const BarnetModel& m, std::span<const TriangleFrame> frames, bool bounded,
                   const std::span<fx::Len> (&skin)[3], fx::Saturation& sat, VectorKernel kernel);

#if defined(__x86_64__)
// wrap_avx2.cpp; called only when the CPU reports AVX2.
void make_triangle_frames_avx2(const BarnetModel& m, const std::span<fx::Len> (&node)[3],
                               std::span<TriangleFrame> frames);
// The frames' first pass alone: every frame's corners, and the
// floor-shifted cross product (shifted_cross) in the normal's place.
void corners_and_crosses_avx2(const BarnetModel& m, const std::span<fx::Len> (&node)[3],
                              std::span<TriangleFrame> frames);
// wrap_avx512.cpp; called only when the CPU reports AVX2 and AVX-512 F + VL
// + CD. The frames with the second pass eight at a time; false (having
// written nothing) when the triangles are too many for its 32-bit word
// indices, which the caller then frames by the AVX2 kernel.
bool make_triangle_frames_avx512(const BarnetModel& m, const std::span<fx::Len> (&node)[3],
                                 std::span<TriangleFrame> frames);
// The bounded wrap; false (having written nothing that matters) when a
// vertex rounds beyond int32, which the caller then wraps by the
// specification, saturation count included.
bool wrap_bounded_avx2(const BarnetModel& m, std::span<const TriangleFrame> frames,
                       const std::span<fx::Len> (&skin)[3]);
#endif

}  // namespace sinew::barnet::detail
