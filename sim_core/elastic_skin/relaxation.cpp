#include "relaxation.hpp"

#include <atomic>

#include "invariant_division.hpp"
#include "relaxation_kernels.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "sim_core/fixed/wide.hpp"
#include "sim_core/layer/range_totals.hpp"
#include "sim_core/muscle/vec_ops.hpp"

namespace sinew::elastic_skin {
namespace {

constexpr int64_t kAccLimit = int64_t{1} << 62;

fx::Vec3 at(const std::span<fx::Len> (&a)[3], uint32_t v) { return {a[0][v], a[1][v], a[2][v]}; }

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

namespace {

// The positions as three plain arrays: the pass's stores cannot then alias
// the spans it reads them through, so nothing is reloaded per edge.
struct Positions {
  const fx::Len* c[3];
  fx::Vec3 operator[](uint32_t v) const { return {c[0][v], c[1][v], c[2][v]}; }
};

Positions positions_of(const std::span<fx::Len> (&position)[3]) {
  return {{position[0].data(), position[1].data(), position[2].data()}};
}

[[gnu::always_inline]] inline bool pull_of(const SkinParams& p, const Edge& e, const Positions& position,
                                           int64_t* k_out, fx::Vec3* f_out) {
  const fx::Vec3 w = fx::sub(position[e.b], position[e.a]);
  const int64_t wc[3] = {w.x, w.y, w.z};
  const uint64_t wx = fx::magnitude(w.x), wy = fx::magnitude(w.y), wz = fx::magnitude(w.z);
  const uint64_t n2 = wx * wx + wy * wy + wz * wz;  // < 3 * 2^62
  if (n2 == 0 || e.k == 0) return false;
  // Elastic force on a: excess along w / |w| = (1 - rest / |w|) w (towards b
  // when stretched).
  const EdgeSpring spring = edge_spring(p, e, n2);
  const int64_t ratio = spring.ratio, k = spring.k;
  if (k == 0) return false;
  // |w_c ratio| <= ||w| - rest| 2^30 (+ rounding) < 2^63: the product fits.
  *f_out = {fx::sat_i32(fx::round_shift(wc[0] * ratio, fx::kUnitFracBits)),
            fx::sat_i32(fx::round_shift(wc[1] * ratio, fx::kUnitFracBits)),
            fx::sat_i32(fx::round_shift(wc[2] * ratio, fx::kUnitFracBits))};
  *k_out = k;
  return true;
}

}  // namespace

bool edge_pull(const SkinParams& p, const Edge& e, const std::span<fx::Len> (&position)[3], int64_t* k_out,
               fx::Vec3* f_out) {
  return pull_of(p, e, positions_of(position), k_out, f_out);
}

namespace {

detail::EdgePullJob pull_job(const SkinModel& model, SkinState* s) {
  return {&model.params,
          model.edges.data(),
          {s->position[0].data(), s->position[1].data(), s->position[2].data()},
          s->moving_edge.data(),
          s->edge_stiffness.data(),
          {s->edge_pull[0].data(), s->edge_pull[1].data(), s->edge_pull[2].data()}};
}

}  // namespace

void detail::pull_edge_scalar(const EdgePullJob& job, uint32_t i) {
  const uint32_t e = job.moving[i];
  int64_t k = 0;
  fx::Vec3 f{};
  if (!pull_of(*job.params, job.edges[e], Positions{{job.position[0], job.position[1], job.position[2]}}, &k, &f)) {
    k = 0;  // pulls with nothing: adds nothing to either end
    f = {0, 0, 0};
  }
  job.stiffness[e] = static_cast<int32_t>(k);  // <= Edge::k <= kMaxStiffness = 2^24
  job.pull[0][e] = f.x;
  job.pull[1][e] = f.y;
  job.pull[2][e] = f.z;
}

void detail::pull_compressed_edge(const EdgePullJob& job, uint32_t e, const int64_t w[3], int64_t ratio, uint64_t n2) {
  const Edge& edge = job.edges[e];
  // edge_spring's compressed branch, then pull_of's products.
  const int64_t k = effective_stiffness(*job.params, edge.k, int64_t{fx::isqrt_fast(n2)} - edge.rest, edge.rest);
  fx::Vec3 f{};
  if (k != 0)
    f = {fx::sat_i32(fx::round_shift(w[0] * ratio, fx::kUnitFracBits)),
         fx::sat_i32(fx::round_shift(w[1] * ratio, fx::kUnitFracBits)),
         fx::sat_i32(fx::round_shift(w[2] * ratio, fx::kUnitFracBits))};
  job.stiffness[e] = static_cast<int32_t>(k);
  job.pull[0][e] = f.x;
  job.pull[1][e] = f.y;
  job.pull[2][e] = f.z;
}

bool detail::relaxation_kernel_supported(RelaxationKernel kernel) {
  switch (kernel) {
    case RelaxationKernel::kScalar:
      return true;
    case RelaxationKernel::kAvx512:
#if defined(__x86_64__)
      return __builtin_cpu_supports("avx512f") != 0 && __builtin_cpu_supports("avx512vl") != 0 &&
             __builtin_cpu_supports("avx512cd") != 0;  // reads CPUID data, no OS call
#else
      return false;
#endif
  }
  return false;
}

detail::RelaxationKernel detail::relaxation_kernel_default() {
  return relaxation_kernel_supported(RelaxationKernel::kAvx512) ? RelaxationKernel::kAvx512 : RelaxationKernel::kScalar;
}

void detail::pull_edges_with(RelaxationKernel kernel, const EdgePullJob& job, uint32_t begin, uint32_t end) {
  uint32_t i = begin;
#if defined(__x86_64__)
  if (kernel == RelaxationKernel::kAvx512 && relaxation_kernel_supported(kernel))
    i = pull_edges_avx512(job, begin, end);
#else
  (void)kernel;
#endif
  for (; i < end; ++i) pull_edge_scalar(job, i);
}

namespace {

// Pass 1 over the moving edges [begin, end) (SkinState::moving_edge): each
// edge's pull, once, by the CPU's kernel (relaxation_kernels.hpp).
void pull_edges(const SkinModel& model, SkinState* s, uint32_t begin, uint32_t end) {
  detail::pull_edges_with(detail::relaxation_kernel_default(), pull_job(model, s), begin, end);
}

// Saturating: the relaxation's definition. The order of terms is part of it
// (add_sat is not associative near its limits). Plain: the same sums for a
// vertex with fewer than kPlainTerms terms. Every term k f has k in [0,
// kMaxStiffness = 2^24] (effective_stiffness never exceeds Edge::k) and
// |f_c| <= 2^31, so |k f_c| <= 2^55, and fewer than 256 of them keep every
// partial sum within 255 * 2^55 < 2^63: add_sat never saturates, and the
// plain sum is its value.
constexpr uint32_t kPlainTerms = 256;
static_assert(uint64_t{kPlainTerms - 1} * (uint64_t{kMaxStiffness} << 31) < (uint64_t{1} << 63));

template <bool Saturating>
struct VertexSums {
  int64_t force[3] = {0, 0, 0};
  int64_t weight = 0;
  [[gnu::always_inline]] void add(int64_t k, fx::Vec3 f) {
    if constexpr (Saturating) {
      force[0] = fx::add_sat_i64(force[0], k * f.x);
      force[1] = fx::add_sat_i64(force[1], k * f.y);
      force[2] = fx::add_sat_i64(force[2], k * f.z);
    } else {
      force[0] += k * f.x;
      force[1] += k * f.y;
      force[2] += k * f.z;
    }
    weight += k;  // <= (edges + bands + 1) * 2^24 per vertex: far from overflow
  }
};

// Vertex v's terms: its edges in edge order, its bands in band order, its
// anchor last.
template <typename Sums>
[[gnu::always_inline]] inline Sums vertex_sums(const SkinModel& model, const muscle::MuscleState& muscles,
                                               const SkinState* s, uint32_t v) {
  Sums sum;
  for (uint32_t i = s->incident_offset[v]; i < s->incident_offset[v + 1]; ++i) {
    const uint32_t e = s->incident_edge[i];
    const fx::Vec3 f{s->edge_pull[0][e], s->edge_pull[1][e], s->edge_pull[2][e]};
    // The pull on a; the opposite on b.
    sum.add(s->edge_stiffness[e],
            s->incident_at_b[i] == 0 ? f : fx::Vec3{fx::neg_sat(f.x), fx::neg_sat(f.y), fx::neg_sat(f.z)});
  }
  const fx::Vec3 p = at(s->position, v);
  for (uint32_t i = s->band_offset[v]; i < s->band_offset[v + 1]; ++i) {
    const RubberBand& b = model.bands[s->band_at[i]];
    const uint32_t m = muscle::muscle_vertex_index(muscles.ring_vertices, b.muscle, b.slice, b.ring_vertex);
    const fx::Vec3 target{muscles.vertex[0][m], muscles.vertex[1][m], muscles.vertex[2][m]};
    sum.add(b.k, fx::sub(target, p));
  }
  sum.add(model.anchor_stiffness[v], fx::sub(at(s->anchor, v), p));
  return sum;
}

VertexSums<false> as_plain(const VertexSums<true>& s) {
  VertexSums<false> p;
  for (int c = 0; c < 3; ++c) p.force[c] = s.force[c];
  p.weight = s.weight;
  return p;
}

struct MoveTotals {
  uint32_t saturated = 0;
  uint64_t largest2 = 0;  // squared relaxation vector length
};

// Pass 2 over the moving vertices [begin, end) (SkinState::moving_vertex):
// each gathers its terms (its edges in
// edge order, its bands in band order, its anchor) and moves.
MoveTotals move_vertices(const SkinModel& model, const muscle::MuscleState& muscles, SkinState* s, uint32_t begin,
                         uint32_t end) {
  MoveTotals t;
  for (uint32_t i = begin; i < end; ++i) {
    const uint32_t v = s->moving_vertex[i];
    const uint32_t terms =
        s->incident_offset[v + 1] - s->incident_offset[v] + s->band_offset[v + 1] - s->band_offset[v] + 1;
    const VertexSums<false> sum = terms < kPlainTerms ? vertex_sums<VertexSums<false>>(model, muscles, s, v)
                                                      : as_plain(vertex_sums<VertexSums<true>>(model, muscles, s, v));
    if (sum.weight <= 0) continue;
    const fx::Vec3 p = at(s->position, v);
    int32_t r[3];
    fx::Saturation sat;
    // One division for the three components: div_round_by is fx::div_round
    // for a positive divisor, bit for bit (invariant_division.hpp).
    const InvariantDivisor by = invariant_divisor(sum.weight);
    for (int c = 0; c < 3; ++c) {
      const int64_t num = fx::clamp_i64(sum.force[c], -kAccLimit + 1, kAccLimit - 1);
      sat.events += static_cast<uint32_t>(num != sum.force[c]);
      r[c] = fx::sat_i32(div_round_by(num, by), sat);
    }
    t.saturated += sat.events;
    const uint64_t x = fx::magnitude(r[0]), y = fx::magnitude(r[1]), z = fx::magnitude(r[2]);
    const uint64_t rl2 = x * x + y * y + z * z;  // < 3 * 2^62 < 2^64, as in fx::length
    if (rl2 > t.largest2) t.largest2 = rl2;
    const fx::Vec3 moved = fx::add(p, {r[0], r[1], r[2]});
    s->position[0][v] = moved.x;
    s->position[1][v] = moved.y;
    s->position[2][v] = moved.z;
  }
  return t;
}

}  // namespace

fx::Len relax_once(const SkinModel& model, const muscle::MuscleState& muscles, SkinState* s,
                   const layer::Workers* workers) {
  const auto edges = [&](uint32_t begin, uint32_t end) {
    pull_edges(model, s, begin, end);
    return 0u;
  };
  layer::run_ranges_summed(workers, s->moving_edges, edges);
  // Jacobi: every pull above is from the positions at the start of the
  // round, and a vertex's move reads only its own position.
  uint32_t saturated = 0;
  const auto vertices = [&](uint32_t begin, uint32_t end) {
    const MoveTotals t = move_vertices(model, muscles, s, begin, end);
    std::atomic_ref<uint32_t>(saturated).fetch_add(t.saturated, std::memory_order_relaxed);
    // floor(sqrt) is monotonic: the largest root is the root of the largest square.
    return static_cast<uint32_t>(fx::sat_i32(int64_t{fx::isqrt_fast(t.largest2)}));
  };
  const uint32_t largest = layer::run_ranges_max(workers, s->moving_vertices, vertices);
  s->stats.saturated += saturated;
  return static_cast<fx::Len>(largest);
}

void place_anchor_spheres(const SkinModel& model, SkinState* s, const layer::Workers* workers) {
  const fx::Len radius = model.params.collision_radius;
  if (radius <= 0) return;
  const auto range = [&](uint32_t begin, uint32_t end) {
    for (uint32_t k = begin; k < end; ++k) {
      const uint32_t v = s->moving_vertex[k];
      const fx::Vec3 normal{s->normal[0][v], s->normal[1][v], s->normal[2][v]};
      // Sphere tangent to the skin's tangent plane at the virtual anchor.
      const fx::Vec3 centre = fx::sub(at(s->anchor, v), muscle::along(normal, radius));
      s->sphere_centre[0][v] = centre.x;
      s->sphere_centre[1][v] = centre.y;
      s->sphere_centre[2][v] = centre.z;
    }
    return 0u;
  };
  layer::run_ranges_summed(workers, s->moving_vertices, range);
}

uint32_t detail::collide_vertex_scalar(const SphereJob& job, uint32_t i) {
  // 2 LSB of slack: a vertex on the sphere (e.g. at its anchor) stays put.
  const int64_t r2 = int64_t{job.radius - 2} * (job.radius - 2);
  const uint32_t v = job.moving[i];
  const fx::Vec3 centre{job.centre[0][v], job.centre[1][v], job.centre[2][v]};
  const fx::Vec3 d = fx::sub({job.position[0][v], job.position[1][v], job.position[2][v]}, centre);
  // Squared distances first: most vertices are outside, no root needed.
  if (fx::dot_wide(d, d) >= r2) return 0;
  // The direction only: the division-free normalisation (exact to
  // rounding, within 2^-28 of unit per component).
  fx::Vec3 dir{};
  const fx::Vec3 out = fx::normalize_fast(d, &dir) ? fx::add(centre, muscle::along(dir, job.radius))
                                                   : fx::Vec3{job.anchor[0][v], job.anchor[1][v], job.anchor[2][v]};
  job.position[0][v] = out.x;
  job.position[1][v] = out.y;
  job.position[2][v] = out.z;
  return 1;
}

uint32_t detail::collide_with_spheres_with(RelaxationKernel kernel, const SphereJob& job, uint32_t begin,
                                           uint32_t end) {
  uint32_t moved = 0;
  uint32_t i = begin;
#if defined(__x86_64__)
  if (kernel == RelaxationKernel::kAvx512 && relaxation_kernel_supported(kernel))
    i = collide_with_spheres_avx512(job, begin, end, &moved);
#else
  (void)kernel;
#endif
  for (; i < end; ++i) moved += collide_vertex_scalar(job, i);
  return moved;
}

uint32_t collide_with_anchor_spheres(const SkinModel& model, SkinState* s, const layer::Workers* workers) {
  const fx::Len radius = model.params.collision_radius;
  if (radius <= 0) return 0;
  const detail::SphereJob job{{s->position[0].data(), s->position[1].data(), s->position[2].data()},
                              {s->sphere_centre[0].data(), s->sphere_centre[1].data(), s->sphere_centre[2].data()},
                              {s->anchor[0].data(), s->anchor[1].data(), s->anchor[2].data()},
                              s->moving_vertex.data(),
                              radius};
  const detail::RelaxationKernel kernel = detail::relaxation_kernel_default();
  return layer::run_ranges_summed(workers, s->moving_vertices, [&](uint32_t begin, uint32_t end) {
    return detail::collide_with_spheres_with(kernel, job, begin, end);
  });
}

}  // namespace sinew::elastic_skin
