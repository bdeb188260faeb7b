// Stage 4: vertices from the normal balls (eq. 4) and the joint balls (eq. 5),
// blended by eq. (1).
#include "kernels.hpp"
#include "rotation.hpp"

namespace sinew::metaballs::detail {

// Eq. (4): v = sum_j w_ij (c_j + s_j R_j d_ij); s_j is the bulge scale, so
// the skin over a bulging ball moves out with its radius. The specification
// the vector kernels are tested against word for word.
void deform_normal_ball_vertex(const MetaballModel& m, const MetaballState& s, uint32_t v,
                               const skin::SkinnedVertices& out) {
  int64_t acc[3] = {0, 0, 0};
  for (uint32_t k = 0; k < kVertexBalls; ++k) {
    const size_t i = size_t{v} * kVertexBalls + k;
    const int64_t w = m.vertex_weight[i];
    if (w == 0) continue;
    const uint16_t b = m.vertex_ball[i];
    int64_t rd[3];
    rotate_q50(s.ball_rotation[b], m.vertex_disp[i], rd);
    const int64_t scale = s.ball_scale[b];
    const fx::Vec3 c = s.ball_center[b];
    const int64_t cc[3] = {c.x, c.y, c.z};
    for (int a = 0; a < 3; ++a) {
      int64_t d = fx::round_shift(rd[a], fx::kUnitFracBits);  // Len, |d| < 2^31
      if (scale != fx::kUnitOne) d = fx::round_shift(d * scale, fx::kUnitFracBits);
      acc[a] += w * (cc[a] + d);  // convex: |sum| < 2^30 * 2^32
    }
  }
  for (int a = 0; a < 3; ++a) out.position[a][v] = fx::sat_i32(fx::round_shift(acc[a], fx::kUnitFracBits));
}

void deform_normal_balls_scalar(const MetaballModel& m, const MetaballState& s, const skin::SkinnedVertices& out) {
  for (uint32_t v = 0; v < m.vertex_count; ++v) deform_normal_ball_vertex(m, s, v, out);
}

bool deform_kernel_supported(DeformKernel kernel) {
  switch (kernel) {
    case DeformKernel::kScalar:
      return true;
    case DeformKernel::kAvx2:
#if defined(__x86_64__)
      return __builtin_cpu_supports("avx2") != 0;  // reads CPUID data, no OS call
#else
      return false;
#endif
  }
  return false;
}

DeformKernel deform_kernel_default() {
  return deform_kernel_supported(DeformKernel::kAvx2) ? DeformKernel::kAvx2 : DeformKernel::kScalar;
}

void deform_vertices(const MetaballModel& m, std::span<const fx::Mat34> joint_model, MetaballState* s,
                     const skin::SkinnedVertices& out, DeformKernel kernel) {
  bool done = false;
#if defined(__x86_64__)
  if (kernel == DeformKernel::kAvx2 && deform_kernel_supported(DeformKernel::kAvx2))
    done = deform_normal_balls_avx2(m, *s, out);
#else
  (void)kernel;
#endif
  if (!done) deform_normal_balls_scalar(m, *s, out);
  if (!s->features.joint_balls) {
    for (uint32_t i = 0; i < m.jv_count(); ++i) s->jv_posed_laplacian[i] = m.jv_laplacian[i];
    return;
  }
  for (uint32_t i = 0; i < m.jv_count(); ++i) {
    const JointBall& jb = m.joint_balls[m.jv_ball[i]];
    // Eq. (5): v = c_eta + R_eta d_eta. The centre is the skeleton joint; the
    // ball is carried equally by both bones, and each vertex turns with the
    // bones' rotations blended by its own weight of the child bone, so
    // vertices attached to different bones get different transformations.
    const fx::Mat34& joint = joint_model[jb.joint];
    const fx::Quat q = nlerp_fast(s->bone_rotation[jb.bone_a], s->bone_rotation[jb.bone_b], m.jv_blend[i]);
    const fx::Rot3 r = fx::rot3_of_unit(q);
    int64_t rd[3], rl[3];
    rotate_q50(r, m.jv_disp[i], rd);
    rotate_q50(r, m.jv_laplacian[i], rl);
    const uint32_t v = m.jv_vertex[i];
    const int64_t alpha = m.jv_alpha[i];
    for (int a = 0; a < 3; ++a) {
      const int64_t eta = fx::sat_i32(int64_t{joint.t[a]} + fx::round_shift(rd[a], fx::kUnitFracBits));
      const int64_t lambda = out.position[a][v];
      // Eq. (1): v = (1 - w_alpha) v_lambda + w_alpha v_eta.
      out.position[a][v] = fx::sat_i32(lambda + fx::round_shift(alpha * (eta - lambda), fx::kUnitFracBits));
    }
    s->jv_posed_laplacian[i] = {fx::sat_i32(fx::round_shift(rl[0], fx::kUnitFracBits)),
                                fx::sat_i32(fx::round_shift(rl[1], fx::kUnitFracBits)),
                                fx::sat_i32(fx::round_shift(rl[2], fx::kUnitFracBits))};
  }
}

}  // namespace sinew::metaballs::detail
