#include "relaxation.hpp"

#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "sim_core/fixed/wide.hpp"
#include "sim_core/muscle/vec_ops.hpp"

namespace sinew::elastic_skin {
namespace {

constexpr int64_t kAccLimit = int64_t{1} << 62;

fx::Vec3 at(const std::span<fx::Len> (&a)[3], uint32_t v) { return {a[0][v], a[1][v], a[2][v]}; }

// Inlined: it runs twice per edge per round, the relaxation's inner loop.
[[gnu::always_inline]] inline void accumulate(SkinState* s, uint32_t v, int64_t k, fx::Vec3 f) {
  s->force[0][v] = fx::add_sat_i64(s->force[0][v], k * f.x);
  s->force[1][v] = fx::add_sat_i64(s->force[1][v], k * f.y);
  s->force[2][v] = fx::add_sat_i64(s->force[2][v], k * f.z);
  s->weight[v] += k;  // <= (edges + bands + 1) * 2^24 per vertex: far from overflow
}

}  // namespace

int64_t effective_stiffness(const SkinParams& p, Stiffness k, int64_t excess, fx::Len rest) {
  if (excess >= 0) return k;
  // Multiplier 1 at excess 0 down to push_back at excess = -band * rest.
  const int64_t band = fx::mul_by_unit(rest, p.compression_band);
  const int64_t one = fx::kUnitOne;
  int64_t m = p.push_back;
  if (band > 0 && -excess < band) m = one - fx::div_round((one - p.push_back) * -excess, band);
  return fx::round_shift(int64_t{k} * m, fx::kUnitFracBits);
}

bool edge_pull(const SkinParams& p, const Edge& e, const std::span<fx::Len> (&position)[3], int64_t* k_out,
               fx::Vec3* f_out) {
  const fx::Vec3 w = fx::sub(at(position, e.b), at(position, e.a));
  const uint64_t wx = fx::magnitude(w.x), wy = fx::magnitude(w.y), wz = fx::magnitude(w.z);
  const int64_t len = fx::isqrt_fast(wx * wx + wy * wy + wz * wz);  // < 3 * 2^62
  const int64_t excess = len - e.rest;
  const int64_t k = effective_stiffness(p, e.k, excess, e.rest);
  // Elastic force on a: excess along w / |w| (towards b when stretched).
  if (k == 0 || len == 0) return false;
  if (len < (int64_t{1} << 30)) {
    // One division per edge: ratio = excess / len in Q2.30, then w * ratio.
    // |w_c| <= len bounds each product by |excess| * 2^30 < 2^62.
    const int64_t ratio = fx::div_round(excess * (int64_t{1} << fx::kUnitFracBits), len);
    *f_out = {fx::sat_i32(fx::round_shift(w.x * ratio, fx::kUnitFracBits)),
              fx::sat_i32(fx::round_shift(w.y * ratio, fx::kUnitFracBits)),
              fx::sat_i32(fx::round_shift(w.z * ratio, fx::kUnitFracBits))};
  } else {  // edges longer than half the Len range: via the unit direction
    fx::Vec3 dir{};
    fx::normalize_to_unit(w, &dir);
    *f_out = muscle::along(dir, fx::sat_i32(excess));
  }
  *k_out = k;
  return true;
}

fx::Len relax_once(const SkinModel& model, const muscle::MuscleState& muscles, SkinState* s) {
  const uint32_t n = model.vertex_count;
  for (int c = 0; c < 3; ++c)
    for (uint32_t v = 0; v < n; ++v) s->force[c][v] = 0;
  for (uint32_t v = 0; v < n; ++v) s->weight[v] = 0;

  for (const Edge& e : model.edges) {
    int64_t k = 0;
    fx::Vec3 f{};
    if (!edge_pull(model.params, e, s->position, &k, &f)) continue;
    accumulate(s, e.a, k, f);
    accumulate(s, e.b, k, {fx::neg_sat(f.x), fx::neg_sat(f.y), fx::neg_sat(f.z)});
  }
  const uint32_t ring = muscles.ring_vertices;
  for (const RubberBand& b : model.bands) {
    const uint32_t m = muscle::muscle_vertex_index(ring, b.muscle, b.slice, b.ring_vertex);
    const fx::Vec3 target{muscles.vertex[0][m], muscles.vertex[1][m], muscles.vertex[2][m]};
    accumulate(s, b.vertex, b.k, fx::sub(target, at(s->position, b.vertex)));
  }
  uint64_t largest = 0;  // squared: floor(sqrt) is monotonic, so one root at the end gives the same length
  for (uint32_t v = 0; v < n; ++v) {
    const fx::Vec3 p = at(s->position, v);
    accumulate(s, v, model.anchor_stiffness[v], fx::sub(at(s->anchor, v), p));
    const int64_t den = s->weight[v];
    if (den <= 0) continue;
    int32_t r[3];
    fx::Saturation sat;
    for (int c = 0; c < 3; ++c) {
      const int64_t num = fx::clamp_i64(s->force[c][v], -kAccLimit + 1, kAccLimit - 1);
      sat.events += static_cast<uint32_t>(num != s->force[c][v]);
      r[c] = fx::sat_i32(fx::div_round(num, den), sat);
    }
    s->stats.saturated += sat.events;
    const fx::Vec3 rv{r[0], r[1], r[2]};
    const uint64_t x = fx::magnitude(rv.x), y = fx::magnitude(rv.y), z = fx::magnitude(rv.z);
    const uint64_t rl2 = x * x + y * y + z * z;  // < 3 * 2^62 < 2^64, as in fx::length
    if (rl2 > largest) largest = rl2;
    const fx::Vec3 moved = fx::add(p, rv);
    s->position[0][v] = moved.x;
    s->position[1][v] = moved.y;
    s->position[2][v] = moved.z;
  }
  return fx::sat_i32(int64_t{fx::isqrt_fast(largest)});
}

uint32_t collide_with_anchor_spheres(const SkinModel& model, SkinState* s) {
  const fx::Len radius = model.params.collision_radius;
  if (radius <= 0) return 0;
  uint32_t moved = 0;
  for (uint32_t v = 0; v < model.vertex_count; ++v) {
    const fx::Vec3 anchor = at(s->anchor, v);
    const fx::Vec3 normal{s->normal[0][v], s->normal[1][v], s->normal[2][v]};
    // Sphere tangent to the skin's tangent plane at the virtual anchor.
    const fx::Vec3 centre = fx::sub(anchor, muscle::along(normal, radius));
    const fx::Vec3 d = fx::sub(at(s->position, v), centre);
    // 2 LSB of slack: a vertex on the sphere (e.g. at its anchor) stays put.
    // Squared distances first: most vertices are outside, no root needed.
    const int64_t r2 = int64_t{radius - 2} * (radius - 2);
    if (fx::dot_wide(d, d) >= r2) continue;
    fx::Vec3 dir{};
    const fx::Vec3 out = fx::normalize_to_unit(d, &dir) ? fx::add(centre, muscle::along(dir, radius)) : anchor;
    s->position[0][v] = out.x;
    s->position[1][v] = out.y;
    s->position[2][v] = out.z;
    ++moved;
  }
  return moved;
}

}  // namespace sinew::elastic_skin
