// Stage 6: surface overlapping. Each ball belongs to one bone's ball set; at a
// joint, vertices of one bone's region found inside a ball of the other
// bone's set and beyond the interior plane are projected orthogonally onto
// that plane (the bisector of the two bone directions through the joint).
// Two bones that share no joint test their listed ball pairs for collision
// and, for each colliding pair, project onto the plane between those two
// balls the vertices of each bone inside the other bone's ball.
#include "kernels.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"

namespace sinew::metaballs::detail {
namespace {

struct Plane {
  fx::Vec3 origin;  // Len
  fx::Vec3 normal;  // Unit, towards bone a
};

// Signed distance (Len) of p from the plane, positive on bone a's side.
int64_t distance(const Plane& pl, fx::Vec3 p) {
  return fx::round_shift(fx::dot_wide(fx::sub(p, pl.origin), pl.normal), fx::kUnitFracBits);
}

// A ball's radius as it stands (bulged), Len, < 2^31.
int64_t radius_now(const MetaballModel& m, const MetaballState& s, uint16_t b) {
  return fx::round_shift(int64_t{m.ball_radius[b]} * s.ball_scale[b], fx::kUnitFracBits);
}

bool inside_any(const MetaballModel& m, const MetaballState& s, std::span<const uint16_t> balls, fx::Vec3 p) {
  for (const uint16_t b : balls) {
    const fx::Vec3 d = fx::sub(p, s.ball_center[b]);
    const uint64_t d2 = static_cast<uint64_t>(int64_t{d.x} * d.x) + static_cast<uint64_t>(int64_t{d.y} * d.y) +
                        static_cast<uint64_t>(int64_t{d.z} * d.z);
    const int64_t r = radius_now(m, s, b);
    if (d2 < static_cast<uint64_t>(r * r)) return true;
  }
  return false;
}

// Projects the listed vertices that lie on the wrong side (sign < 0 means
// "must stay on the positive side") and inside one of the other set's balls.
uint32_t project_side(const MetaballModel& m, const MetaballState& s, const Plane& pl, int64_t side,
                      std::span<const uint32_t> vertices, std::span<const uint16_t> other_balls,
                      const skin::SkinnedVertices& out) {
  uint32_t projected = 0;
  for (const uint32_t v : vertices) {
    const fx::Vec3 p{out.position[0][v], out.position[1][v], out.position[2][v]};
    const int64_t dist = side * distance(pl, p);
    if (dist >= 0 || !inside_any(m, s, other_balls, p)) continue;
    const int64_t along = side * dist;  // signed distance again
    out.position[0][v] = fx::sat_i32(p.x - fx::round_shift(along * pl.normal.x, fx::kUnitFracBits));
    out.position[1][v] = fx::sat_i32(p.y - fx::round_shift(along * pl.normal.y, fx::kUnitFracBits));
    out.position[2][v] = fx::sat_i32(p.z - fx::round_shift(along * pl.normal.z, fx::kUnitFracBits));
    ++projected;
  }
  return projected;
}

// Whether p lies inside ball b.
bool inside_ball(const MetaballModel& m, const MetaballState& s, uint16_t b, fx::Vec3 p) {
  const fx::Vec3 d = fx::sub(p, s.ball_center[b]);
  const uint64_t d2 = static_cast<uint64_t>(int64_t{d.x} * d.x) + static_cast<uint64_t>(int64_t{d.y} * d.y) +
                      static_cast<uint64_t>(int64_t{d.z} * d.z);
  const int64_t r = radius_now(m, s, b);
  return d2 < static_cast<uint64_t>(r * r);
}

// Whether balls a and b overlap at rest (one tissue: never a collision).
bool touch_at_rest(const MetaballModel& m, uint16_t a, uint16_t b) {
  const fx::Vec3 d = fx::sub(m.ball_rest[a], m.ball_rest[b]);
  const uint64_t d2 = static_cast<uint64_t>(int64_t{d.x} * d.x) + static_cast<uint64_t>(int64_t{d.y} * d.y) +
                      static_cast<uint64_t>(int64_t{d.z} * d.z);
  const auto reach = static_cast<uint64_t>(int64_t{m.ball_radius[a]} + m.ball_radius[b]);  // < 2^32
  return d2 < reach * reach;
}

// Whether balls a and b overlap now (bulged radii).
bool touch_now(const MetaballModel& m, const MetaballState& s, uint16_t a, uint16_t b) {
  const fx::Vec3 d = fx::sub(s.ball_center[a], s.ball_center[b]);
  const uint64_t d2 = static_cast<uint64_t>(int64_t{d.x} * d.x) + static_cast<uint64_t>(int64_t{d.y} * d.y) +
                      static_cast<uint64_t>(int64_t{d.z} * d.z);
  const auto reach = static_cast<uint64_t>(radius_now(m, s, a) + radius_now(m, s, b));  // < 2^32
  return d2 < reach * reach;
}

// Projects vertex v (of the bone of ball `own`, which it follows most) onto
// the interior plane between `own` and the other bone's ball `other` when it
// lies beyond it: normal (c_own - c_other) / |c_own - c_other|, through
// c_other + n (|c_own - c_other| + r_other - r_own) / 2, midway through the
// two balls' overlap. True if it moved.
bool project_between(const MetaballModel& m, const MetaballState& s, uint16_t own, uint16_t other, uint32_t v,
                     const skin::SkinnedVertices& out) {
  const fx::Vec3 d = fx::sub(s.ball_center[own], s.ball_center[other]);
  Plane pl;
  if (!fx::normalize_fast(d, &pl.normal)) return false;  // concentric: no side to push to
  const uint64_t d2 = static_cast<uint64_t>(int64_t{d.x} * d.x) + static_cast<uint64_t>(int64_t{d.y} * d.y) +
                      static_cast<uint64_t>(int64_t{d.z} * d.z);
  const int64_t offset = (int64_t{fx::isqrt_fast(d2)} + radius_now(m, s, other) - radius_now(m, s, own)) / 2;
  pl.origin = fx::add(s.ball_center[other], {fx::sat_i32(fx::round_shift(offset * pl.normal.x, fx::kUnitFracBits)),
                                             fx::sat_i32(fx::round_shift(offset * pl.normal.y, fx::kUnitFracBits)),
                                             fx::sat_i32(fx::round_shift(offset * pl.normal.z, fx::kUnitFracBits))});
  const fx::Vec3 p{out.position[0][v], out.position[1][v], out.position[2][v]};
  const int64_t along = distance(pl, p);
  if (along >= 0) return false;
  out.position[0][v] = fx::sat_i32(p.x - fx::round_shift(along * pl.normal.x, fx::kUnitFracBits));
  out.position[1][v] = fx::sat_i32(p.y - fx::round_shift(along * pl.normal.y, fx::kUnitFracBits));
  out.position[2][v] = fx::sat_i32(p.z - fx::round_shift(along * pl.normal.z, fx::kUnitFracBits));
  return true;
}

// One side of a record of two bones: each listed vertex is tested against
// the other bone's balls that collide with its own ball (its first,
// heaviest, of eq. (4)) now and not at rest; inside one and beyond the
// plane between the two, it is projected onto that plane, then tested
// against the next (in list order).
uint32_t project_side_between(const MetaballModel& m, const MetaballState& s, std::span<const uint32_t> vertices,
                              std::span<const uint16_t> other_balls, const skin::SkinnedVertices& out) {
  uint32_t projected = 0;
  for (const uint32_t v : vertices) {
    const uint16_t own = m.vertex_ball[size_t{v} * kVertexBalls];
    if (own == kNoBall || s.ball_touching[own] == 0) continue;
    bool moved = false;
    for (const uint16_t other : other_balls) {
      if (s.ball_touching[other] == 0 || other == own || !touch_now(m, s, own, other) || touch_at_rest(m, own, other))
        continue;
      const fx::Vec3 p{out.position[0][v], out.position[1][v], out.position[2][v]};
      if (inside_ball(m, s, other, p)) moved = project_between(m, s, own, other, v, out) || moved;
    }
    projected += moved ? 1u : 0u;
  }
  return projected;
}

// A record of two bones that share no joint (OverlapRecord, kNoJoint): the
// ball sets detect their collision (pairs apart at rest that overlap now),
// then the vertices of each bone inside the other's colliding balls.
uint32_t resolve_bone_pair(const MetaballModel& m, const MetaballState& s, const OverlapRecord& r,
                           const skin::SkinnedVertices& out) {
  const auto balls_a = m.overlap_balls.subspan(r.balls_a_begin, r.balls_a_end - r.balls_a_begin);
  const auto balls_b = m.overlap_balls.subspan(r.balls_b_begin, r.balls_b_end - r.balls_b_begin);
  for (const uint16_t a : balls_a) s.ball_touching[a] = 0;
  for (const uint16_t b : balls_b) s.ball_touching[b] = 0;
  bool any = false;
  for (const uint16_t a : balls_a)
    for (const uint16_t b : balls_b)
      if (touch_now(m, s, a, b) && !touch_at_rest(m, a, b)) s.ball_touching[a] = s.ball_touching[b] = 1, any = true;
  if (!any) return 0;
  const auto vertices_a = m.overlap_vertices.subspan(r.vertices_a_begin, r.vertices_a_end - r.vertices_a_begin);
  const auto vertices_b = m.overlap_vertices.subspan(r.vertices_b_begin, r.vertices_b_end - r.vertices_b_begin);
  return project_side_between(m, s, vertices_a, balls_b, out) + project_side_between(m, s, vertices_b, balls_a, out);
}

}  // namespace

uint32_t resolve_overlaps(const MetaballModel& m, std::span<const fx::Mat34> joint_model, const MetaballState& s,
                          const skin::SkinnedVertices& out) {
  uint32_t projected = 0;
  for (const OverlapRecord& r : m.overlaps) {
    if (r.joint == kNoJoint) {
      projected += resolve_bone_pair(m, s, r, out);
      continue;
    }
    const fx::Vec3 da = fx::transform_vector(s.bone[r.bone_a], r.dir_a);  // Unit
    const fx::Vec3 db = fx::transform_vector(s.bone[r.bone_b], r.dir_b);
    Plane pl;
    if (!fx::normalize_fast(fx::sub(da, db), &pl.normal)) continue;  // bones folded onto each other
    const fx::Mat34& j = joint_model[r.joint];
    pl.origin = {j.t[0], j.t[1], j.t[2]};
    const auto verts = [&](uint32_t b, uint32_t e) { return m.overlap_vertices.subspan(b, e - b); };
    const auto balls = [&](uint32_t b, uint32_t e) { return m.overlap_balls.subspan(b, e - b); };
    projected += project_side(m, s, pl, +1, verts(r.vertices_a_begin, r.vertices_a_end),
                              balls(r.balls_b_begin, r.balls_b_end), out);
    projected += project_side(m, s, pl, -1, verts(r.vertices_b_begin, r.vertices_b_end),
                              balls(r.balls_a_begin, r.balls_a_end), out);
  }
  return projected;
}

}  // namespace sinew::metaballs::detail
