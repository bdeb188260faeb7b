#include "validate.hpp"

#include "sim_core/rig/message.hpp"

namespace sinew::metaballs {
namespace {

constexpr int64_t kOne = fx::kUnitOne;
// Positions and displacements keep one bit of headroom, so c + s R d (s < 3)
// and every blended sum stay far inside int64 before their single rounding.
constexpr int64_t kCoordLimit = int64_t{1} << 30;

class Checker {
 public:
  explicit Checker(LayerStatus* s) : s_(s) {}
  bool failed() const { return !s_->ok(); }
  // Records the first failure: "<field>[<index>]: <problem>".
  bool fail(LayerError e, const char* field, int64_t index, const char* problem, int64_t value = INT64_MIN) {
    if (failed()) return false;
    s_->error = e;
    rig::MessageBuilder m(s_->message, sizeof(s_->message));
    m.text(field);
    if (index >= 0) m.text("[").number(index).text("]");
    m.text(": ").text(problem);
    if (value != INT64_MIN) m.text(" (").number(value).text(")");
    return false;
  }
  bool size(const char* field, size_t got, size_t want) {
    if (got == want) return true;
    return fail(LayerError::kBadSize, field, -1, "length disagrees with the counts", static_cast<int64_t>(got));
  }
  bool limit(const char* field, size_t got, size_t max, size_t min = 0) {
    if (got >= min && got <= max) return true;
    return fail(LayerError::kBadCount, field, -1, got < min ? "count below the minimum" : "count beyond the maximum",
                static_cast<int64_t>(got));
  }
  bool index(const char* field, size_t i, int64_t v, int64_t end) {
    if (v >= 0 && v < end) return true;
    return fail(LayerError::kBadIndex, field, static_cast<int64_t>(i), "index out of range", v);
  }
  bool range(const char* field, size_t i, int64_t v, int64_t lo, int64_t hi) {
    if (v >= lo && v <= hi) return true;
    return fail(LayerError::kBadValue, field, static_cast<int64_t>(i), "value out of range", v);
  }
  bool scalar(const char* field, int64_t v, int64_t lo, int64_t hi) {
    if (v >= lo && v <= hi) return true;
    return fail(LayerError::kBadValue, field, -1, "value out of range", v);
  }
  bool coords(const char* field, size_t i, fx::Vec3 v) {
    return range(field, i, v.x, -kCoordLimit, kCoordLimit) && range(field, i, v.y, -kCoordLimit, kCoordLimit) &&
           range(field, i, v.z, -kCoordLimit, kCoordLimit);
  }
  bool unit_dir(const char* field, size_t i, fx::Vec3 v) {
    const int64_t n2 = fx::dot_wide(v, v);  // Q60; unit within ~2^-18
    if (n2 > (kOne * kOne) - (int64_t{1} << 43) && n2 < (kOne * kOne) + (int64_t{1} << 43)) return true;
    return fail(LayerError::kBadValue, field, static_cast<int64_t>(i), "not a unit direction");
  }

 private:
  LayerStatus* s_;
};

void check_balls(const MetaballModel& m, Checker& c) {
  const size_t nb = m.ball_count(), nj = m.joint_count;
  if (!c.limit("ball_rest", nb, kMaxBalls, 1) || !c.size("ball_radius", m.ball_radius.size(), nb) ||
      !c.size("ball_bone", m.ball_bone.size(), nb) || !c.size("ball_jiggle", m.ball_jiggle.size(), nb) ||
      !c.size("ball_joint", m.ball_joint.size(), nb * kBallInfluences) ||
      !c.size("ball_weight", m.ball_weight.size(), nb * kBallInfluences))
    return;
  for (size_t b = 0; b < nb && !c.failed(); ++b) {
    c.coords("ball_rest", b, m.ball_rest[b]);
    c.range("ball_radius", b, m.ball_radius[b], 1, kCoordLimit);
    c.index("ball_bone", b, m.ball_bone[b], static_cast<int64_t>(nj));
    c.range("ball_jiggle", b, m.ball_jiggle[b], 0, kOne);
    int64_t sum = 0;
    for (size_t k = 0; k < kBallInfluences; ++k) {
      const size_t i = b * kBallInfluences + k;
      c.index("ball_joint", i, m.ball_joint[i], static_cast<int64_t>(nj));
      c.range("ball_weight", i, m.ball_weight[i], 0, kOne);
      sum += m.ball_weight[i];
    }
    if (sum != kOne)
      c.fail(LayerError::kBadValue, "ball_weight", static_cast<int64_t>(b), "weights do not sum to 2^30", sum);
  }
  if (!c.limit("pairs", m.pairs.size(), kMaxPairs)) return;
  for (size_t p = 0; p < m.pairs.size() && !c.failed(); ++p) {
    const BallPair& q = m.pairs[p];
    c.index("pairs.a", p, q.a, static_cast<int64_t>(nb));
    c.index("pairs.b", p, q.b, static_cast<int64_t>(nb));
    if (q.a == q.b) c.fail(LayerError::kBadIndex, "pairs.b", static_cast<int64_t>(p), "a ball paired with itself", q.b);
    c.range("pairs.rest", p, q.rest, 1, kCoordLimit);
    c.range("pairs.share_a", p, q.share_a, 0, kOne);
    c.range("pairs.share_b", p, q.share_b, 0, kOne);
    if (int64_t{q.share_a} + q.share_b != kOne)
      c.fail(LayerError::kBadValue, "pairs.share_b", static_cast<int64_t>(p), "shares do not sum to 2^30");
    c.range("pairs.stiffness", p, q.stiffness, 0, kOne);
    if (m.jiggle_rate_hz == 0 || c.failed()) continue;
    // A coupled pair (jiggle_gains.hpp): a spring that pulls its jiggle balls.
    if (q.stiffness == 0) c.fail(LayerError::kBadValue, "pairs.stiffness", static_cast<int64_t>(p), "no coupling");
    if (m.ball_jiggle[q.a] == 0 && m.ball_jiggle[q.b] == 0)
      c.fail(LayerError::kBadValue, "pairs.a", static_cast<int64_t>(p), "a coupled pair without a jiggle ball");
  }
  if (!c.limit("action_lines", m.action_lines.size(), kMaxActionLines)) return;
  for (size_t i = 0; i < m.action_lines.size() && !c.failed(); ++i) {
    const ActionLine& l = m.action_lines[i];
    c.index("action_lines.origin_bone", i, l.origin_bone, static_cast<int64_t>(nj));
    c.index("action_lines.insertion_bone", i, l.insertion_bone, static_cast<int64_t>(nj));
    c.coords("action_lines.origin_rest", i, l.origin_rest);
    c.coords("action_lines.insertion_rest", i, l.insertion_rest);
  }
  if (!c.limit("action_balls", m.action_balls.size(), kMaxActionBalls)) return;
  for (size_t i = 0; i < m.action_balls.size() && !c.failed(); ++i) {
    const ActionBall& a = m.action_balls[i];
    c.index("action_balls.ball", i, a.ball, static_cast<int64_t>(nb));
    c.index("action_balls.line", i, a.line, static_cast<int64_t>(m.action_lines.size()));
    c.range("action_balls.along", i, a.along, 0, kOne);
    c.range("action_balls.rest", i, a.rest, 0, kCoordLimit);
    c.range("action_balls.stiffness", i, a.stiffness, 0, kOne);
  }
  if (!c.limit("bulges", m.bulges.size(), nb)) return;
  for (size_t i = 0; i < m.bulges.size() && !c.failed(); ++i) {
    const BulgeRecord& r = m.bulges[i];
    c.index("bulges.ball", i, r.ball, static_cast<int64_t>(nb));
    c.index("bulges.bone_a", i, r.bone_a, static_cast<int64_t>(nj));
    c.index("bulges.bone_b", i, r.bone_b, static_cast<int64_t>(nj));
    c.range("bulges.gain", i, r.gain, 0, kOne - 1);
  }
  c.scalar("pbd_iterations", m.pbd_iterations, 0, kMaxPbdIterations);
  c.scalar("jiggle_damping", m.jiggle_damping, 0, kOne - 1);
}

void check_vertices(const MetaballModel& m, Checker& c) {
  const size_t nv = m.vertex_count, nb = m.ball_count();
  if (!c.size("vertex_ball", m.vertex_ball.size(), nv * kVertexBalls) ||
      !c.size("vertex_weight", m.vertex_weight.size(), nv * kVertexBalls) ||
      !c.size("vertex_disp", m.vertex_disp.size(), nv * kVertexBalls))
    return;
  for (size_t v = 0; v < nv && !c.failed(); ++v) {
    int64_t sum = 0;
    for (size_t k = 0; k < kVertexBalls; ++k) {
      const size_t i = v * kVertexBalls + k;
      const fx::Unit w = m.vertex_weight[i];
      c.range("vertex_weight", i, w, 0, kOne);
      if (w != 0) c.index("vertex_ball", i, m.vertex_ball[i], static_cast<int64_t>(nb));
      c.coords("vertex_disp", i, m.vertex_disp[i]);
      sum += w;
    }
    if (sum != kOne)
      c.fail(LayerError::kBadValue, "vertex_weight", static_cast<int64_t>(v), "weights do not sum to 2^30", sum);
  }
}

void check_joint_region(const MetaballModel& m, Checker& c) {
  const size_t nj = m.joint_count, nv = m.vertex_count, n = m.jv_count();
  if (!c.limit("joint_balls", m.joint_balls.size(), kMaxJointBalls)) return;
  for (size_t i = 0; i < m.joint_balls.size() && !c.failed(); ++i) {
    const JointBall& j = m.joint_balls[i];
    c.index("joint_balls.joint", i, j.joint, static_cast<int64_t>(nj));
    c.index("joint_balls.bone_a", i, j.bone_a, static_cast<int64_t>(nj));
    c.index("joint_balls.bone_b", i, j.bone_b, static_cast<int64_t>(nj));
    c.coords("joint_balls.rest_center", i, j.rest_center);
  }
  if (!c.limit("jv_vertex", n, nv) || !c.size("jv_ball", m.jv_ball.size(), n) ||
      !c.size("jv_alpha", m.jv_alpha.size(), n) || !c.size("jv_blend", m.jv_blend.size(), n) ||
      !c.size("jv_disp", m.jv_disp.size(), n) || !c.size("jv_laplacian", m.jv_laplacian.size(), n) ||
      !c.size("jv_inv_count", m.jv_inv_count.size(), n) ||
      !c.size("jv_neighbour_begin", m.jv_neighbour_begin.size(), n + 1))
    return;
  if (m.jv_neighbour_begin[0] != 0 || m.jv_neighbour_begin[n] != m.jv_neighbours.size())
    return void(c.fail(LayerError::kBadIndex, "jv_neighbour_begin", 0, "does not span jv_neighbours"));
  for (size_t i = 0; i < n && !c.failed(); ++i) {
    c.index("jv_vertex", i, m.jv_vertex[i], static_cast<int64_t>(nv));
    if (i > 0 && m.jv_vertex[i] <= m.jv_vertex[i - 1])
      c.fail(LayerError::kBadIndex, "jv_vertex", static_cast<int64_t>(i), "not strictly ascending", m.jv_vertex[i]);
    c.index("jv_ball", i, m.jv_ball[i], static_cast<int64_t>(m.joint_balls.size()));
    c.range("jv_alpha", i, m.jv_alpha[i], 1, kOne);
    c.range("jv_blend", i, m.jv_blend[i], 0, kOne);
    c.coords("jv_disp", i, m.jv_disp[i]);
    c.coords("jv_laplacian", i, m.jv_laplacian[i]);
    const uint32_t b = m.jv_neighbour_begin[i], e = m.jv_neighbour_begin[i + 1];
    if (e < b || e - b > kMaxNeighbours)
      return void(c.fail(LayerError::kBadCount, "jv_neighbour_begin", static_cast<int64_t>(i),
                         "neighbour count negative or beyond the maximum"));
    const int64_t cnt = e - b;  // round half up of 2^30 / cnt
    const int64_t want = cnt == 0 ? 0 : (2 * kOne + cnt) / (2 * cnt);
    if (m.jv_inv_count[i] != want)
      c.fail(LayerError::kBadValue, "jv_inv_count", static_cast<int64_t>(i), "is not 2^30 / neighbour count",
             m.jv_inv_count[i]);
    for (uint32_t k = b; k < e && !c.failed(); ++k)
      c.index("jv_neighbours", k, m.jv_neighbours[k], static_cast<int64_t>(nv));
  }
  c.scalar("smoothing_passes", m.smoothing_passes, 0, kMaxSmoothingPasses);
  c.scalar("smoothing_rate", m.smoothing_rate, 0, kOne);
}

void check_overlaps(const MetaballModel& m, Checker& c) {
  const size_t nj = m.joint_count, nv = m.vertex_count, nb = m.ball_count();
  const size_t ov = m.overlap_vertices.size(), ob = m.overlap_balls.size();
  if (!c.limit("overlaps", m.overlaps.size(), kMaxOverlaps) ||
      !c.limit("overlap_balls", m.overlap_balls.size(), kMaxOverlapBalls))
    return;
  for (size_t i = 0; i < ov && !c.failed(); ++i)
    c.index("overlap_vertices", i, m.overlap_vertices[i], static_cast<int64_t>(nv));
  for (size_t i = 0; i < ob && !c.failed(); ++i)
    c.index("overlap_balls", i, m.overlap_balls[i], static_cast<int64_t>(nb));
  uint64_t work = 0;
  for (size_t i = 0; i < m.overlaps.size() && !c.failed(); ++i) {
    const OverlapRecord& r = m.overlaps[i];
    const bool bone_pair = r.joint == kNoJoint;
    if (!bone_pair) c.index("overlaps.joint", i, r.joint, static_cast<int64_t>(nj));
    c.index("overlaps.bone_a", i, r.bone_a, static_cast<int64_t>(nj));
    c.index("overlaps.bone_b", i, r.bone_b, static_cast<int64_t>(nj));
    if (r.bone_a == r.bone_b) c.fail(LayerError::kBadIndex, "overlaps.bone_b", static_cast<int64_t>(i), "bone_a again");
    if (!bone_pair) {
      c.unit_dir("overlaps.dir_a", i, r.dir_a);
      c.unit_dir("overlaps.dir_b", i, r.dir_b);
    }
    if (r.vertices_a_begin > r.vertices_a_end || r.vertices_a_end > ov || r.vertices_b_begin > r.vertices_b_end ||
        r.vertices_b_end > ov)
      c.fail(LayerError::kBadIndex, "overlaps.vertices", static_cast<int64_t>(i), "range outside overlap_vertices");
    if (r.balls_a_begin > r.balls_a_end || r.balls_a_end > ob || r.balls_b_begin > r.balls_b_end || r.balls_b_end > ob)
      c.fail(LayerError::kBadIndex, "overlaps.balls", static_cast<int64_t>(i), "range outside overlap_balls");
    if (c.failed()) return;
    const uint64_t va = r.vertices_a_end - r.vertices_a_begin, vb = r.vertices_b_end - r.vertices_b_begin;
    const uint64_t ba = r.balls_a_end - r.balls_a_begin, bb = r.balls_b_end - r.balls_b_begin;
    work += va * bb + vb * ba + (bone_pair ? ba * bb : 0);  // a record of two bones tests its ball pairs too
  }
  if (!c.failed() && work > kMaxOverlapWork)
    c.fail(LayerError::kBadCount, "overlaps", -1, "vertex-ball tests per step beyond the maximum",
           static_cast<int64_t>(work));
}

}  // namespace

LayerStatus metaballs_validate_model(const MetaballModel& m) {
  LayerStatus s;
  Checker c(&s);
  if (!c.limit("joint_count", m.joint_count, kMaxJoints, 1) ||
      !c.limit("vertex_count", m.vertex_count, kMaxVertices, 1) ||
      !c.size("inverse_bind", m.inverse_bind.size(), m.joint_count))
    return s;
  check_balls(m, c);
  if (!c.failed()) check_vertices(m, c);
  if (!c.failed()) check_joint_region(m, c);
  if (!c.failed()) check_overlaps(m, c);
  return s;
}

LayerStatus metaballs_validate(const MetaballModel& m, const rig::Rig& rig) {
  LayerStatus s;
  Checker c(&s);
  if (m.joint_count != rig.joint_count())
    c.fail(LayerError::kBadCount, "joint_count", -1, "differs from the rig's", m.joint_count);
  else if (m.vertex_count != rig.vertex_count())
    c.fail(LayerError::kBadCount, "vertex_count", -1, "differs from the rig's", m.vertex_count);
  else
    s = metaballs_validate_model(m);
  return s;
}

}  // namespace sinew::metaballs
