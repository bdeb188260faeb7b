// Stage 4: vertices from the normal balls (eq. 4) and the joint balls (eq. 5),
// blended by eq. (1), each as one rigid motion of the vertex's rest
// displacement (docs/metaballs.md, "Rotations blended before they act").
#include "kernels.hpp"
#include "rotation.hpp"

namespace sinew::metaballs::detail {

uint16_t vertex_rotation(const MetaballModel& m, const MetaballState& s, uint32_t v, fx::Quat* quat,
                         fx::Rot3* rotation) {
  const size_t base = size_t{v} * kVertexBalls;
  uint16_t shared = kNoBall;
  bool alike = true;
  for (uint32_t k = 0; k < kVertexBalls; ++k) {
    if (m.vertex_weight[base + k] == 0) continue;
    const uint16_t b = m.vertex_ball[base + k];
    if (shared == kNoBall) shared = b;
    alike = alike && s.ball_quat[b] == s.ball_quat[shared];
  }
  if (alike) return shared;
  QuatBlend blend;
  for (uint32_t k = 0; k < kVertexBalls; ++k)
    if (m.vertex_weight[base + k] != 0) blend.add(s.ball_quat[m.vertex_ball[base + k]], m.vertex_weight[base + k]);
  *quat = blend.unit();
  *rotation = fx::rot3_of_unit(*quat);
  return kNoBall;
}

// Eq. (4) with the balls' rotations blended before they act:
//   v = sum_j w_j c_j + R (sum_j w_j s_j d_ij),  R = nlerp_j(w_j, R_j),
// equal to eq. (4) wherever the vertex's balls turn alike, and a rigid
// motion of the vertex's ring where they do not (eq. 4 as written blends
// differently rotated displacements linearly, which shrinks the section like
// LBS where the balls' rotations change fast along a bone, e.g. a twist).
NormalBallFrame normal_ball_frame(const MetaballModel& m, const MetaballState& s, uint32_t v) {
  int64_t centre[3] = {0, 0, 0}, disp[3] = {0, 0, 0};  // Q30 x Len: |sum| < 2^30 * 2^32
  bool any = false;
  for (uint32_t k = 0; k < kVertexBalls; ++k) {
    const size_t i = size_t{v} * kVertexBalls + k;
    const int64_t w = m.vertex_weight[i];
    if (w == 0) continue;
    any = true;
    const uint16_t b = m.vertex_ball[i];
    const fx::Vec3 c = s.ball_center[b], d0 = m.vertex_disp[i];
    const int64_t cc[3] = {c.x, c.y, c.z};
    int64_t d[3] = {d0.x, d0.y, d0.z};
    const int64_t scale = s.ball_scale[b];
    for (int a = 0; a < 3; ++a) {
      if (scale != fx::kUnitOne) d[a] = fx::round_shift(d[a] * scale, fx::kUnitFracBits);  // |s d| < 2^32
      centre[a] += w * cc[a];
      disp[a] += w * d[a];
    }
  }
  NormalBallFrame f{};
  if (!any) return f;  // no weight (not a validated model): the origin
  for (int a = 0; a < 3; ++a) f.centre[a] = fx::round_shift(centre[a], fx::kUnitFracBits);
  f.disp = {fx::sat_i32(fx::round_shift(disp[0], fx::kUnitFracBits)),
            fx::sat_i32(fx::round_shift(disp[1], fx::kUnitFracBits)),
            fx::sat_i32(fx::round_shift(disp[2], fx::kUnitFracBits))};
  const uint16_t shared = vertex_rotation(m, s, v, &f.quat, &f.rotation);
  if (shared != kNoBall) {
    f.quat = s.ball_quat[shared];
    f.rotation = s.ball_rotation[shared];
  }
  return f;
}

// The specification the vector kernels are tested against word for word:
// v = c + round(R D) from the frame above, saturated.
void deform_normal_ball_vertex(const MetaballModel& m, const MetaballState& s, uint32_t v,
                               const skin::SkinnedVertices& out) {
  const NormalBallFrame f = normal_ball_frame(m, s, v);
  int64_t rd[3];
  rotate_q50(f.rotation, f.disp, rd);
  for (int a = 0; a < 3; ++a) out.position[a][v] = fx::sat_i32(f.centre[a] + fx::round_shift(rd[a], fx::kUnitFracBits));
}

bool balls_turn_alike(const MetaballModel& m, const MetaballState& s, uint32_t v) {
  const size_t base = size_t{v} * kVertexBalls;
  const fx::Quat* first = nullptr;
  for (uint32_t k = 0; k < kVertexBalls; ++k) {
    if (m.vertex_weight[base + k] == 0) continue;
    const fx::Quat& q = s.ball_quat[m.vertex_ball[base + k]];
    if (first == nullptr) {
      first = &q;
    } else if (!(q == *first)) {
      return false;
    }
  }
  return true;
}

size_t first_skip_at(std::span<const uint32_t> skip, uint32_t begin) {
  size_t lo = 0, hi = skip.size();
  while (lo < hi) {
    const size_t mid = lo + (hi - lo) / 2;
    if (skip[mid] < begin) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  return lo;
}

uint16_t ball_bone(const MetaballModel& m, uint32_t b) {
  const fx::Unit* w = &m.ball_weight[size_t{b} * kBallInfluences];
  static_assert(kBallInfluences == 2);
  if (w[0] != 0 && w[1] != 0) return kNoBall;                              // a ball of two bones turns with their blend
  return m.ball_joint[size_t{b} * kBallInfluences + (w[0] != 0 ? 0 : 1)];  // as compute_balls picks it
}

bool one_bone_balls_follow_bones(const MetaballModel& m, const MetaballState& s) {
  bool follow = true;
  for (uint32_t b = 0; b < m.ball_count(); ++b) {
    const uint16_t bone = ball_bone(m, b);
    follow = follow && (bone == kNoBall || s.ball_quat[b] == s.bone_rotation[bone]);
  }
  return follow;
}

void deform_normal_balls_scalar(const MetaballModel& m, const MetaballState& s, const skin::SkinnedVertices& out,
                                std::span<const uint32_t> skip, uint32_t begin, uint32_t end,
                                const TurnedVertices* turned) {
  if (end > m.vertex_count) end = m.vertex_count;
  size_t next = first_skip_at(skip, begin);
  const bool follow = turned != nullptr && one_bone_balls_follow_bones(m, s);
  for (uint32_t v = begin; v < end; ++v) {
    if (next < skip.size() && skip[next] == v) {
      ++next;
      continue;
    }
    if (turned != nullptr && !(follow && s.vertex_bone[v] != kNoBall) && !balls_turn_alike(m, s, v)) {
      turned->take(turned->context, v);
      continue;
    }
    deform_normal_ball_vertex(m, s, v, out);
  }
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

void make_rest_blends(const MetaballModel& m, MetaballState* s) {
  for (uint32_t v = 0; v < m.vertex_count; ++v) {
    int64_t rest[3] = {0, 0, 0}, disp[3] = {0, 0, 0};  // Q30 x Len, as in joint_region_frame
    uint16_t bone = kNoBall;
    bool one_bone = true;
    for (uint32_t k = 0; k < kVertexBalls; ++k) {
      const size_t i = size_t{v} * kVertexBalls + k;
      const int64_t w = m.vertex_weight[i];
      if (w == 0) continue;  // its ball index is not checked by validation
      const uint16_t b = ball_bone(m, m.vertex_ball[i]);
      if (bone == kNoBall) bone = b;
      one_bone = one_bone && b != kNoBall && b == bone;
      const fx::Vec3 c0 = m.ball_rest[m.vertex_ball[i]], d0 = m.vertex_disp[i];
      rest[0] += w * c0.x, rest[1] += w * c0.y, rest[2] += w * c0.z;
      disp[0] += w * d0.x, disp[1] += w * d0.y, disp[2] += w * d0.z;
    }
    const auto q30 = [](int64_t x) { return fx::sat_i32(fx::round_shift(x, fx::kUnitFracBits)); };
    s->vertex_rest_centre[v] = {q30(rest[0]), q30(rest[1]), q30(rest[2])};
    s->vertex_rest_disp[v] = {q30(disp[0]), q30(disp[1]), q30(disp[2])};
    s->vertex_bone[v] = one_bone ? bone : kNoBall;
  }
}

// Each ball's frame F_b(x) = c_b + R_b (x - c0_b) as a dual quaternion:
// rotation R_b, translation c_b - R_b c0_b (|c0| <= 2^30: exact in Q50).
void make_ball_frames(const MetaballModel& m, MetaballState* s) {
  bool near_unit = true;
  for (uint32_t b = 0; b < m.ball_count(); ++b) {
    int64_t rc[3];
    rotate_q50(s->ball_rotation[b], m.ball_rest[b], rc);
    const fx::Vec3 c = s->ball_center[b];
    const fx::Vec3 t{fx::sat_i32(int64_t{c.x} - fx::round_shift(rc[0], fx::kUnitFracBits)),
                     fx::sat_i32(int64_t{c.y} - fx::round_shift(rc[1], fx::kUnitFracBits)),
                     fx::sat_i32(int64_t{c.z} - fx::round_shift(rc[2], fx::kUnitFracBits))};
    s->ball_frame[b] = fx::dual_quat_from_rt(s->ball_quat[b], t);
    const fx::Quat& r = s->ball_frame[b].real;
    for (const int64_t q : {r.w, r.x, r.y, r.z}) near_unit = near_unit && q >= -kFrameRealLimit && q <= kFrameRealLimit;
  }
  s->ball_frames_near_unit = near_unit;
}

namespace {

// fx::transform_point(dq, p) word for word, for the dq that DualQuatBlend::unit
// returns, with its rotation matrix r = rot3_of_unit(dq.real) made once by the
// caller (rot3_of_unit equals fx::rotate's rot3_from_quat on near-unit
// quaternions, where no saturation can occur). No sum below can saturate:
// |r_ij| <= 2^30 + 16 and |p| < 2^31 give |R p| sums < 2^63, and by
// Cauchy-Schwarz |dual . real| <= 2^32 (2^30 + 8) < 2^63 for every partial sum.
fx::Vec3 transform_point_unit(const fx::DualQuat& dq, const fx::Rot3& r, fx::Vec3 p) {
  const int64_t a[4] = {dq.dual.w, dq.dual.x, dq.dual.y, dq.dual.z};
  const int64_t w = dq.real.w, x = -int64_t{dq.real.x}, y = -int64_t{dq.real.y}, z = -int64_t{dq.real.z};
  // translation_of: 2 (dual * conjugate(real)).xyz, each rounded from Q50 once.
  const int64_t t[3] = {a[0] * x + a[1] * w + (a[2] * z - a[3] * y), a[0] * y - a[1] * z + (a[2] * w + a[3] * x),
                        a[0] * z + a[1] * y + (-(a[2] * x) + a[3] * w)};
  int32_t out[3];
  for (int i = 0; i < 3; ++i) {
    const int64_t rp = int64_t{r.m[i][0]} * p.x + int64_t{r.m[i][1]} * p.y + int64_t{r.m[i][2]} * p.z;
    const int32_t rotated = fx::sat_i32(fx::round_shift(rp, fx::kUnitFracBits));
    const int32_t moved = fx::sat_i32(int64_t{fx::sat_i32(fx::round_shift(t[i], fx::kUnitFracBits))} * 2);
    out[i] = fx::add_sat(rotated, moved);
  }
  return {out[0], out[1], out[2]};
}

}  // namespace

// Eq. (4) as one rigid motion on the arc: the dual-quaternion blend of the
// vertex's balls' frames by its weights, applied to sum_j w_j (c0_j + s_j
// d_ij). Equal to eq. (4) wherever the balls turn alike; where they do not,
// eq. (4) as written (and the nlerp frame of normal_ball_frame) blends
// their centres along the chord, which near a bent joint shortens the tube
// (docs/metaballs.md, "Balls of two bones"). Written as a frame: the
// displacement D = sum_j w_j s_j d_ij, the rotation the blend's, and the
// centre the blend applied to sum_j w_j c0_j.
NormalBallFrame joint_region_frame(const MetaballModel& m, const MetaballState& s, uint32_t v) {
  const size_t base = size_t{v} * kVertexBalls;
  DualQuatBlend blend;
  int64_t rest[3] = {0, 0, 0}, disp[3] = {0, 0, 0};
  for (uint32_t k = 0; k < kVertexBalls; ++k) {
    const fx::Unit weight = m.vertex_weight[base + k];
    if (weight == 0) continue;
    const uint16_t b = m.vertex_ball[base + k];
    blend.add(s.ball_frame[b], weight);
    const fx::Vec3 c0 = m.ball_rest[b], d0 = m.vertex_disp[base + k];
    const int64_t scale = s.ball_scale[b];
    const int64_t c[3] = {c0.x, c0.y, c0.z};
    int64_t dd[3] = {d0.x, d0.y, d0.z};
    for (int a = 0; a < 3; ++a) {
      if (scale != fx::kUnitOne) dd[a] = fx::round_shift(dd[a] * scale, fx::kUnitFracBits);  // |s d| < 2^32
      rest[a] += int64_t{weight} * c[a];
      disp[a] += int64_t{weight} * dd[a];
    }
  }
  NormalBallFrame f{};
  if (!blend.any) return f;  // no weight (not a validated model): the origin
  const auto q30 = [](int64_t x) { return fx::sat_i32(fx::round_shift(x, fx::kUnitFracBits)); };
  const fx::DualQuat dq = blend.unit();
  f.quat = dq.real;
  f.rotation = fx::rot3_of_unit(dq.real);
  const fx::Vec3 centre = transform_point_unit(dq, f.rotation, {q30(rest[0]), q30(rest[1]), q30(rest[2])});
  f.centre[0] = centre.x;
  f.centre[1] = centre.y;
  f.centre[2] = centre.z;
  f.disp = {q30(disp[0]), q30(disp[1]), q30(disp[2])};
  return f;
}

void joint_region_frames(const MetaballModel& m, const MetaballState& s, std::span<const uint32_t> vertices,
                         std::span<NormalBallFrame> frames, [[maybe_unused]] DeformKernel kernel) {
#if defined(__x86_64__)
  if (kernel == DeformKernel::kAvx2 && deform_kernel_supported(DeformKernel::kAvx2))
    return joint_region_frames_avx2(m, s, vertices, frames);
#endif
  for (size_t i = 0; i < vertices.size(); ++i) frames[i] = joint_region_frame(m, s, vertices[i]);
}

// Eq. (5): v_eta = c_eta + R_eta d_eta. The centre is the skeleton joint;
// the ball is carried equally by both bones, and each vertex turns with the
// bones' rotations blended by its own weight of the child bone (eta, made by
// the caller), so vertices attached to different bones get different
// transformations.
// Eq. (1), v = (1 - w_alpha) v_lambda + w_alpha v_eta, as one rigid motion:
// centre and rest displacement blended linearly, the two rotations by
// nlerp. Equal to eq. (1) where R_lambda = R_eta, and it keeps the ring's
// section where they differ (a linear blend of two rotations by an angle
// apart shrinks it by cos(angle / 2)).
void blend_joint_region_entry(const MetaballModel& m, std::span<const fx::Mat34> joint_model, const NormalBallFrame& f,
                              const fx::Quat& eta, uint32_t i, MetaballState* s, const skin::SkinnedVertices& out) {
  const fx::Mat34& joint = joint_model[m.joint_balls[m.jv_ball[i]].joint];
  const int64_t alpha = m.jv_alpha[i];
  const fx::Rot3 r = fx::rot3_of_unit(nlerp_fast(f.quat, eta, m.jv_alpha[i]));
  const int64_t jt[3] = {joint.t[0], joint.t[1], joint.t[2]};
  const fx::Vec3 de = m.jv_disp[i];
  const int64_t d_eta[3] = {de.x, de.y, de.z}, d_lambda[3] = {f.disp.x, f.disp.y, f.disp.z};
  fx::Vec3 d;
  int32_t* dc[3] = {&d.x, &d.y, &d.z};
  int64_t centre[3];
  for (int a = 0; a < 3; ++a) {
    // |joint - centre| < 2^32 and |d_eta - d_lambda| < 2^32: products < 2^62.
    centre[a] = f.centre[a] + fx::round_shift(alpha * (jt[a] - f.centre[a]), fx::kUnitFracBits);
    *dc[a] = fx::sat_i32(d_lambda[a] + fx::round_shift(alpha * (d_eta[a] - d_lambda[a]), fx::kUnitFracBits));
  }
  int64_t rd[3], rl[3];
  rotate_q50(r, d, rd);
  rotate_q50(r, m.jv_laplacian[i], rl);
  const uint32_t v = m.jv_vertex[i];
  for (int a = 0; a < 3; ++a) out.position[a][v] = fx::sat_i32(centre[a] + fx::round_shift(rd[a], fx::kUnitFracBits));
  s->jv_posed_laplacian[i] = {fx::sat_i32(fx::round_shift(rl[0], fx::kUnitFracBits)),
                              fx::sat_i32(fx::round_shift(rl[1], fx::kUnitFracBits)),
                              fx::sat_i32(fx::round_shift(rl[2], fx::kUnitFracBits))};
}

void blend_joint_region_entries(const MetaballModel& m, std::span<const fx::Mat34> joint_model,
                                std::span<const NormalBallFrame* const> frames, std::span<const fx::Quat> eta,
                                uint32_t first, MetaballState* s, const skin::SkinnedVertices& out,
                                [[maybe_unused]] DeformKernel kernel) {
#if defined(__x86_64__)
  if (kernel == DeformKernel::kAvx2 && deform_kernel_supported(DeformKernel::kAvx2))
    return blend_joint_region_entries_avx2(m, joint_model, frames, eta, first, s, out);
#endif
  for (uint32_t k = 0; k < frames.size(); ++k)
    blend_joint_region_entry(m, joint_model, *frames[k], eta[k], first + k, s, out);
}

namespace {

// Frames are made for this many vertices at a time (stack buffers of 2.8 KiB).
constexpr uint32_t kFrameBatch = 32;

struct DeformJob {
  const MetaballModel* m;
  std::span<const fx::Mat34> joint_model;
  MetaballState* s;
  const skin::SkinnedVertices* out;
  std::span<const uint32_t> skip;
  DeformKernel kernel;
};

// The turned vertices of one range, a batch of frames at a time: each frame
// on the arc, then R D and the centre written.
struct ArcBatch {
  const MetaballModel* m = nullptr;
  const MetaballState* s = nullptr;
  const skin::SkinnedVertices* out = nullptr;
  DeformKernel kernel = DeformKernel::kScalar;
  uint32_t count = 0;
  uint32_t pending[kFrameBatch];
  NormalBallFrame frames[kFrameBatch];

  // c + R D of frame f with the vertex's displacement blend D.
  void place(const NormalBallFrame& f, fx::Vec3 disp, uint32_t v) const {
    int64_t rd[3];
    rotate_q50(f.rotation, disp, rd);
    for (int a = 0; a < 3; ++a)
      out->position[a][v] = fx::sat_i32(f.centre[a] + fx::round_shift(rd[a], fx::kUnitFracBits));
  }
  void flush() {
    joint_region_frames(*m, *s, {pending, count}, {frames, count}, kernel);
    for (uint32_t k = 0; k < count; ++k) place(frames[k], frames[k].disp, pending[k]);
    count = 0;
  }
  static void take(void* context, uint32_t v) {
    ArcBatch& b = *static_cast<ArcBatch*>(context);
    if (const NormalBallFrame* shared = shared_frame_of(*b.s, v))  // its key's frame, made this step
      return b.place(*shared, vertex_disp_blend(*b.m, *b.s, v), v);
    b.pending[b.count++] = v;
    if (b.count == kFrameBatch) b.flush();
  }
};

// Vertices [begin, end) outside the joint regions: eq. (4) by the kernel
// where the vertex's balls turn alike (a rigid motion), and where they turn
// differently (balls of two bones near a joint) eq. (4) on the arc
// (joint_region_frame) instead of the kernels' nlerp frame, whose centre
// blends along the chord. Each vertex is computed once. Writes only these
// vertices' positions.
void deform_outside_joint_regions(void* context, uint32_t begin, uint32_t end) {
  const DeformJob& j = *static_cast<const DeformJob*>(context);
  const MetaballModel& m = *j.m;
  const MetaballState& s = *j.s;
  const skin::SkinnedVertices& out = *j.out;
  // The vertices whose balls turn differently come back from the kernel's
  // alike test, a batch of frames at a time.
  ArcBatch arc;
  arc.m = &m;
  arc.s = &s;
  arc.out = &out;
  arc.kernel = j.kernel;
  const TurnedVertices turned{ArcBatch::take, &arc};
  bool done = false;
#if defined(__x86_64__)
  if (j.kernel == DeformKernel::kAvx2 && deform_kernel_supported(DeformKernel::kAvx2))
    done = deform_normal_balls_avx2(m, s, out, j.skip, begin, end, &turned);
#endif
  if (!done) deform_normal_balls_scalar(m, s, out, j.skip, begin, end, &turned);
  arc.flush();
}

// Joint-region entries [begin, end) (jv_*): eq. (5) blended by eq. (1).
// Writes only these entries' vertices and jv_posed_laplacian.
void deform_joint_regions(void* context, uint32_t begin, uint32_t end) {
  const DeformJob& j = *static_cast<const DeformJob*>(context);
  const MetaballModel& m = *j.m;
  MetaballState* s = j.s;
  // The vertices of one ring share their joint ball and blend, so eta is
  // made once per ring (kept with what it was made from; a range starts
  // afresh, so eta is the same function of its ring in every range).
  uint16_t eta_ball = kNoBall;
  fx::Unit eta_blend = 0;
  fx::Quat ring_eta{};
  // A batch of entries at a time: v_lambda's frames (eq. 4 on the arc) for
  // the entries below w_alpha = 1, then eq. (1) for every entry.
  static constexpr NormalBallFrame kNoFrame{};
  // Their frames are their keys' (shared_vertex_frame) where they have one,
  // else made here.
  uint32_t pending[kFrameBatch], pending_slot[kFrameBatch];
  NormalBallFrame frames[kFrameBatch], made[kFrameBatch];
  const NormalBallFrame* frame_of[kFrameBatch];
  fx::Quat eta[kFrameBatch];
  for (uint32_t batch = begin; batch < end; batch += kFrameBatch) {
    const uint32_t count = end - batch < kFrameBatch ? end - batch : kFrameBatch;
    uint32_t lambdas = 0, unshared = 0;
    for (uint32_t k = 0; k < count; ++k) {
      if (m.jv_alpha[batch + k] == fx::kUnitOne) continue;
      const uint32_t v = m.jv_vertex[batch + k];
      if (!shared_vertex_frame(m, *s, v, &frames[lambdas])) pending[unshared] = v, pending_slot[unshared++] = lambdas;
      ++lambdas;
    }
    joint_region_frames(m, *s, {pending, unshared}, {made, unshared}, j.kernel);
    for (uint32_t k = 0; k < unshared; ++k) frames[pending_slot[k]] = made[k];
    uint32_t taken = 0;
    for (uint32_t k = 0; k < count; ++k) {
      const uint32_t i = batch + k;
      // At w_alpha = 1 eq. (1) is eq. (5) alone, word for word (the blends of
      // blend_joint_region_entry return their second term exactly), so
      // v_lambda is not made.
      frame_of[k] = m.jv_alpha[i] == fx::kUnitOne ? &kNoFrame : &frames[taken++];
      if (m.jv_ball[i] != eta_ball || m.jv_blend[i] != eta_blend) {
        const JointBall& jb = m.joint_balls[m.jv_ball[i]];
        eta_ball = m.jv_ball[i];
        eta_blend = m.jv_blend[i];
        ring_eta = nlerp_fast(s->bone_rotation[jb.bone_a], s->bone_rotation[jb.bone_b], eta_blend);
      }
      eta[k] = ring_eta;
    }
    blend_joint_region_entries(m, j.joint_model, {frame_of, count}, {eta, count}, batch, s, *j.out, j.kernel);
  }
}

}  // namespace

void deform_vertices(const MetaballModel& m, std::span<const fx::Mat34> joint_model, MetaballState* s,
                     const skin::SkinnedVertices& out, DeformKernel kernel, const layer::Workers* workers) {
  // The balls' frames first (serial, one per ball): both vertex loops read them.
  make_ball_frames(m, s);
  // Then the frames on the arc of every (balls, weights) key (parallel, one
  // per key): both vertex loops read them too.
  make_shared_frames(m, s, kernel, workers);
  // Eq. (1) below computes the joint-region vertices from their own frames.
  DeformJob job{&m, joint_model, s, &out, s->features.joint_balls ? m.jv_vertex : std::span<const uint32_t>{}, kernel};
  layer::run_ranges(workers, m.vertex_count, deform_outside_joint_regions, &job);
  if (!s->features.joint_balls) {
    for (uint32_t i = 0; i < m.jv_count(); ++i) s->jv_posed_laplacian[i] = m.jv_laplacian[i];
    return;
  }
  layer::run_ranges(workers, m.jv_count(), deform_joint_regions, &job);
}

}  // namespace sinew::metaballs::detail
