// Stage 5: Laplacian smoothing of the joint-region vertices, as a
// shape-preserving filter (local Laplacian coordinates): each pass moves a
// vertex towards mean(neighbours) - R delta_rest, so a region that is a rigid
// motion of the rest shape is left alone and only the roughness of the
// blended boundary is smoothed. Jacobi passes (read all, then write all), so
// the result does not depend on vertex order.
#include "kernels.hpp"

namespace sinew::metaballs::detail {

void smooth_joint_region(const MetaballModel& m, MetaballState* s, const skin::SkinnedVertices& out) {
  if (!s->features.smoothing || !s->features.joint_balls) return;
  const uint32_t n = m.jv_count();
  for (uint32_t pass = 0; pass < m.smoothing_passes; ++pass) {
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t v = m.jv_vertex[i];
      const uint32_t begin = m.jv_neighbour_begin[i], end = m.jv_neighbour_begin[i + 1];
      const int64_t p[3] = {out.position[0][v], out.position[1][v], out.position[2][v]};
      fx::Vec3 next{static_cast<int32_t>(p[0]), static_cast<int32_t>(p[1]), static_cast<int32_t>(p[2])};
      if (begin != end) {
        int64_t sum[3] = {0, 0, 0};  // <= 16 differences of int32: < 2^37
        for (uint32_t k = begin; k < end; ++k)
          for (int a = 0; a < 3; ++a) sum[a] += out.position[a][m.jv_neighbours[k]] - p[a];
        const int64_t gain = fx::mul_unit(m.smoothing_rate, m.jv_alpha[i]);
        const fx::Vec3 rest = s->jv_posed_laplacian[i];
        const int64_t lap_rest[3] = {rest.x, rest.y, rest.z};
        int32_t* out_c[3] = {&next.x, &next.y, &next.z};
        for (int a = 0; a < 3; ++a) {
          // mean offset: sum * (2^30 / count) stays < 2^62 since count *
          // inv_count ~ 2^30.
          const int64_t mean = fx::round_shift(sum[a] * m.jv_inv_count[i], fx::kUnitFracBits);
          const int64_t delta = fx::clamp_i64(mean - lap_rest[a], -(int64_t{1} << 32), int64_t{1} << 32);
          *out_c[a] = fx::sat_i32(p[a] + fx::round_shift(delta * gain, fx::kUnitFracBits));
        }
      }
      s->jv_scratch[i] = next;
    }
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t v = m.jv_vertex[i];
      out.position[0][v] = s->jv_scratch[i].x;
      out.position[1][v] = s->jv_scratch[i].y;
      out.position[2][v] = s->jv_scratch[i].z;
    }
  }
}

}  // namespace sinew::metaballs::detail
