#include "sph_state.hpp"

#include "sim_core/fixed/arena.hpp"
#include "sim_core/rig/message.hpp"
#include "sph_grid.hpp"
#include "sph_kernels.hpp"
#include "sph_pose.hpp"

namespace sinew::sph {
namespace {

using Carver = fx::ArenaCarver;

uint32_t grid_dim_of(const SphParams& p) { return static_cast<uint32_t>((2 * int64_t{p.grid_radius} + p.h - 1) / p.h); }

Carver layout(const SphModel& m, uint8_t* base, size_t size, SphState* s) {
  Carver c(base, size);
  const size_t n = m.particle_count(), sv = m.skin_count();
  const size_t d = grid_dim_of(m.params), cells = d * d * d;
  for (int a = 0; a < 3; ++a) {
    s->position[a] = c.take<fx::Len>(n);
    s->velocity[a] = c.take<fx::Len>(n);
    s->ideal[a] = c.take<fx::Len>(n);
    s->scratch[a] = c.take<fx::Len>(n);
    s->skin_offset[a] = c.take<fx::Len>(sv);
  }
  s->pressure = c.take<Dens>(n);
  s->yielded = c.take<uint8_t>(n);
  s->density = c.take<Dens>(n);
  s->rest_density = c.take<Dens>(n);
  s->inv_density = c.take<fx::Unit>(n);
  s->cell = c.take<uint32_t>(n);
  s->cell_start = c.take<uint32_t>(cells + 1);
  s->sorted = c.take<uint16_t>(n);
  for (int a = 0; a < 3; ++a) {
    s->sorted_position[a] = c.take<fx::Len>(n);
    s->pressure_sum[a] = c.take<int64_t>(n);
    s->viscosity_sum[a] = c.take<int64_t>(n);
  }
  const size_t colour = m.params.tension_gain != 0 ? n : 0;
  for (int a = 0; a < 3; ++a) s->colour_gradient_sum[a] = c.take<int64_t>(colour);
  s->colour_laplacian_sum = c.take<int64_t>(colour);
  // Every stored pair gives at least one particle a neighbour, so n x
  // max_neighbours bound them unless a list overflows; the search over the
  // workers gives each range of r particles r x (max_neighbours + 1)
  // entries, its last the spare of the search's unconditional store
  // (sph_grid.cpp).
  const size_t pairs = n * (m.params.max_neighbours + size_t{1}) + 1;
  s->pairs = c.take<SphPair>(pairs);
  s->run_first = c.take<uint32_t>(n);
  s->run_count = c.take<uint16_t>(n);
  s->b_offset = c.take<uint32_t>(n + 1);
  s->b_pair = c.take<uint32_t>(pairs);
  s->candidates = c.take<SphCandidate>(n * m.params.max_neighbours);
  for (int a = 0; a < 3; ++a) s->candidate_origin[a] = c.take<fx::Len>(n);
  s->candidate_first = c.take<uint32_t>(n);
  s->candidate_end = c.take<uint32_t>(n);
  s->neighbour_count = c.take<uint16_t>(n);
  s->density_sum = c.take<int64_t>(n);
  s->skin_particle = c.take<uint16_t>(sv * kMaxVertexNeighbours);
  s->skin_weight = c.take<int32_t>(sv * kMaxVertexNeighbours);
  s->skin_count = c.take<uint8_t>(sv);
  s->grid_dim = static_cast<uint32_t>(d);
  return c;
}

LayerStatus fail(LayerError e, const char* what) {
  LayerStatus s;
  s.error = e;
  rig::MessageBuilder(s.message, sizeof s.message).text("sph init: ").text(what);
  return s;
}

// Kernel weights of eq. (2) between each skin vertex and the particles, at
// rest: the interpolation is embedded in the rest configuration (constant
// weights), only the particles' displacements and densities change.
void skin_weights(SphState* st, fx::Vec3 centre) {
  const SphModel& m = *st->model;
  const uint32_t d = st->grid_dim;
  const InvH ih = make_inv_h(m.params.h);
  for (uint32_t v = 0; v < m.skin_count(); ++v) {
    const fx::Vec3 pv{m.skin_rest[0][v], m.skin_rest[1][v], m.skin_rest[2][v]};
    const uint32_t c = cell_index(*st, centre, pv);
    const int32_t cx = static_cast<int32_t>(c % d), cy = static_cast<int32_t>((c / d) % d),
                  cz = static_cast<int32_t>(c / (d * d));
    uint32_t count = 0;
    for (int32_t z = cz - 1; z <= cz + 1; ++z)
      for (int32_t y = cy - 1; y <= cy + 1; ++y)
        for (int32_t x = cx - 1; x <= cx + 1; ++x) {
          if (x < 0 || y < 0 || z < 0 || x >= static_cast<int32_t>(d) || y >= static_cast<int32_t>(d) ||
              z >= static_cast<int32_t>(d))
            continue;
          const uint32_t cc = (static_cast<uint32_t>(z) * d + static_cast<uint32_t>(y)) * d + static_cast<uint32_t>(x);
          for (uint32_t k = st->cell_start[cc]; k < st->cell_start[cc + 1] && count < kMaxVertexNeighbours; ++k) {
            const uint32_t j = st->sorted[k];
            PairGeometry g;
            if (!pair_geometry(pv, {st->position[0][j], st->position[1][j], st->position[2][j]}, ih, &g)) continue;
            st->skin_particle[size_t{v} * kMaxVertexNeighbours + count] = static_cast<uint16_t>(j);
            st->skin_weight[size_t{v} * kMaxVertexNeighbours + count] = poly6(g.s);
            ++count;
          }
        }
    st->skin_count[v] = static_cast<uint8_t>(count);
  }
}

}  // namespace

size_t sph_state_bytes(const SphModel& model) {
  SphState probe;
  probe.model = &model;
  return layout(model, nullptr, 0, &probe).needed();
}

LayerStatus sph_init(const SphModel& model, std::span<const fx::Mat34> rest_transforms, void* arena, size_t arena_bytes,
                     SphState* out) {
  LayerStatus status = sph_validate_model(model);
  if (!status.ok()) return status;
  if (arena == nullptr || (reinterpret_cast<uintptr_t>(arena) & 7u) != 0)
    return fail(LayerError::kArena, "arena is null or not 8-byte aligned");
  SphState s;
  s.model = &model;
  if (layout(model, static_cast<uint8_t*>(arena), arena_bytes, &s).failed())
    return fail(LayerError::kArena, "arena smaller than sph_state_bytes(model)");
  JointFrame f;
  if (!joint_frame(model, rest_transforms, &f))
    return fail(LayerError::kBadInput, "rest_transforms shorter than the joints");
  // Rest density of every particle, from its rest neighbourhood: the state of
  // minimum principal stress (§4.2) and the reference of the equation of state.
  for (int a = 0; a < 3; ++a)
    for (uint32_t i = 0; i < model.particle_count(); ++i) s.position[a][i] = model.rest_model[a][i];
  build_neighbours(&s, f.centre);
  compute_density(&s);
  sort_into_cells(&s, f.centre);  // skin_weights walks the cells
  skin_weights(&s, f.centre);
  for (uint32_t i = 0; i < model.particle_count(); ++i) s.rest_density[i] = s.density[i];
  // Rotational inertia of the distal particles about the axis (equal masses).
  int64_t inertia = 0;
  for (uint32_t i = 0; i < model.particle_count(); ++i) {
    if (model.bone[i] != static_cast<uint8_t>(Bone::kDistal)) continue;
    const fx::Vec3 r = fx::sub({model.rest_model[0][i], model.rest_model[1][i], model.rest_model[2][i]}, f.centre);
    const fx::Vec3 rp = fx::cross(f.axis, r, 30);          // |axis x r| = |r_perp|
    inertia += fx::round_shift(fx::dot_wide(rp, rp), 28);  // Q40 -> Q12
  }
  if (inertia <= 0) return fail(LayerError::kBadValue, "distal particles have no lever arm about the joint axis");
  s.inertia_q12 = inertia;
  *out = s;
  status = sph_reset(out, rest_transforms);
  out->stats = {};
  return status;
}

LayerStatus sph_reset(SphState* st, std::span<const fx::Mat34> transforms) {
  JointFrame f;
  if (st == nullptr || st->model == nullptr) return fail(LayerError::kBadInput, "state is not initialised");
  if (!joint_frame(*st->model, transforms, &f))
    return fail(LayerError::kBadInput, "transforms shorter than the joints");
  compute_ideal(st, f);
  const uint32_t n = st->model->particle_count();
  for (int a = 0; a < 3; ++a)
    for (uint32_t i = 0; i < n; ++i) {
      st->position[a][i] = st->ideal[a][i];
      st->velocity[a][i] = 0;
    }
  for (uint32_t i = 0; i < n; ++i) {
    st->density[i] = st->rest_density[i];
    st->pressure[i] = 0;
    st->yielded[i] = 0;
    st->inv_density[i] = static_cast<fx::Unit>(fx::div_round(int64_t{1} << 54, st->rest_density[i]));
  }
  for (int a = 0; a < 3; ++a)
    for (uint32_t v = 0; v < st->model->skin_count(); ++v) st->skin_offset[a][v] = 0;
  st->bend = 0;
  st->joint_yielded = false;
  st->yielded_particles = 0;
  st->yield_torque_q12 = 0;
  st->distal_flexed = *f.distal;
  return {};
}

}  // namespace sinew::sph
