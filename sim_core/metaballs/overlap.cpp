// Stage 6: surface overlapping. Each ball belongs to one bone's ball set; at a
// joint, vertices of one bone's region found inside a ball of the other
// bone's set and beyond the interior plane are projected orthogonally onto
// that plane (the bisector of the two bone directions through the joint).
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

bool inside_any(const MetaballModel& m, const MetaballState& s, std::span<const uint16_t> balls, fx::Vec3 p) {
  for (const uint16_t b : balls) {
    const fx::Vec3 d = fx::sub(p, s.ball_center[b]);
    const uint64_t d2 = static_cast<uint64_t>(int64_t{d.x} * d.x) + static_cast<uint64_t>(int64_t{d.y} * d.y) +
                        static_cast<uint64_t>(int64_t{d.z} * d.z);
    const int64_t r = fx::round_shift(int64_t{m.ball_radius[b]} * s.ball_scale[b],
                                      fx::kUnitFracBits);  // < 2^31
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

}  // namespace

uint32_t resolve_overlaps(const MetaballModel& m, std::span<const fx::Mat34> joint_model, const MetaballState& s,
                          const skin::SkinnedVertices& out) {
  uint32_t projected = 0;
  for (const OverlapRecord& r : m.overlaps) {
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
