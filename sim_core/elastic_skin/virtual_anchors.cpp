#include "virtual_anchors.hpp"

#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/wide.hpp"
#include "sim_core/muscle/vec_ops.hpp"

namespace sinew::elastic_skin {
namespace {

int64_t comp(fx::Vec3 v, int c) { return c == 0 ? v.x : (c == 1 ? v.y : v.z); }

// Normalised by the division-free reciprocal square root: it runs for
// every skin vertex every tick.
fx::Vec3 unit_blend(fx::Vec3 a, fx::Vec3 b, fx::Unit w) {
  const fx::Vec3 mixed = fx::add(a, fx::scale(fx::sub(b, a), w));
  fx::Vec3 n{};
  return fx::normalize_fast(mixed, &n) ? n : a;
}

}  // namespace

void muscle_cell(const muscle::MuscleState& m, uint32_t muscle, uint32_t segment, fx::Vec3 corners[8]) {
  const uint32_t ring = m.ring_vertices;
  const uint32_t js[4] = {0, ring / 4, ring / 2, 3 * ring / 4};
  for (uint32_t side = 0; side < 2; ++side)
    for (uint32_t c = 0; c < 4; ++c) {
      const uint32_t at = muscle::muscle_vertex_index(ring, muscle, segment + side, js[c]);
      corners[side * 4 + c] = {m.vertex[0][at], m.vertex[1][at], m.vertex[2][at]};
    }
}

fx::Vec3 trilinear(const fx::Vec3 corners[8], const fx::Lin param[3]) {
  constexpr int kQ = fx::kLinFracBits;
  const int64_t s = param[0], t = param[1], u = param[2];
  const int64_t st = fx::mul_shift_round(s, t, kQ);
  int64_t out[3];
  for (int c = 0; c < 3; ++c) {
    int64_t slice[2];
    for (int side = 0; side < 2; ++side) {
      const fx::Vec3* q = corners + side * 4;
      const int64_t c00 = comp(q[0], c), c10 = comp(q[1], c), c11 = comp(q[2], c), c01 = comp(q[3], c);
      // B(s, t) = c00 + s (c10 - c00) + t (c01 - c00) + s t (c11 - c10 - c01 + c00)
      slice[side] = c00 + fx::mul_shift_round(c10 - c00, s, kQ) + fx::mul_shift_round(c01 - c00, t, kQ) +
                    fx::mul_shift_round(c11 - c10 - c01 + c00, st, kQ);
    }
    out[c] = slice[0] + fx::mul_shift_round(slice[1] - slice[0], u, kQ);
  }
  return {fx::sat_i32(out[0]), fx::sat_i32(out[1]), fx::sat_i32(out[2])};
}

AnchorPoint map_anchor(const Anchor& a, std::span<const fx::Mat34> bones, const muscle::MuscleState& m) {
  AnchorPoint p;
  if (a.kind == static_cast<uint8_t>(AnchorKind::kBone)) {
    const fx::Mat34& ba = bones[a.component];
    const fx::Mat34& bb = bones[a.bone_b];
    const fx::Vec3 pa = fx::transform_point(ba, a.local_a);
    if (a.weight_b == 0) {  // one bone: what the blend below gives with w = 0, without the second bone
      p.position = pa;
      p.normal = unit_blend(fx::transform_vector(ba, a.normal_a), {0, 0, 0}, 0);
      return p;
    }
    const fx::Vec3 pb = fx::transform_point(bb, a.local_b);
    p.position = fx::add(pa, fx::scale(fx::sub(pb, pa), a.weight_b));
    p.normal = unit_blend(fx::transform_vector(ba, a.normal_a), fx::transform_vector(bb, a.normal_b), a.weight_b);
    return p;
  }
  fx::Vec3 corners[8];
  muscle_cell(m, a.component, a.segment, corners);
  p.position = trilinear(corners, a.param);
  // The normal rides on the slice frames, blended between the two slices by u.
  const muscle::SliceFrame& f0 = m.frames[a.component * muscle::kSlices + a.segment];
  const muscle::SliceFrame& f1 = m.frames[a.component * muscle::kSlices + a.segment + 1];
  const auto in_frame = [&](const muscle::SliceFrame& f) {
    return fx::add(fx::add(muscle::along(f.x, a.normal_a.x), muscle::along(f.y, a.normal_a.y)),
                   muscle::along(f.z, a.normal_a.z));
  };
  const int64_t u = fx::clamp_i64(a.param[2], 0, fx::kLinOne);
  p.normal = unit_blend(in_frame(f0), in_frame(f1), fx::sat_i32(u << (fx::kUnitFracBits - fx::kLinFracBits)));
  return p;
}

}  // namespace sinew::elastic_skin
