#include "sph_grid.hpp"

#include "sph_kernels.hpp"

namespace sinew::sph {
namespace {

uint32_t axis_cell(const SphState& st, int32_t centre, int32_t p) {
  const SphParams& pr = st.model->params;
  const int64_t off = int64_t{p} - (int64_t{centre} - pr.grid_radius);
  if (off <= 0) return 0;
  const uint64_t c = static_cast<uint64_t>(off) / static_cast<uint64_t>(pr.h);
  return c >= st.grid_dim ? st.grid_dim - 1 : static_cast<uint32_t>(c);
}

}  // namespace

uint32_t cell_index(const SphState& st, fx::Vec3 centre, fx::Vec3 p) {
  const uint32_t d = st.grid_dim;
  return (axis_cell(st, centre.z, p.z) * d + axis_cell(st, centre.y, p.y)) * d + axis_cell(st, centre.x, p.x);
}

void build_neighbours(SphState* st, fx::Vec3 centre) {
  const SphModel& m = *st->model;
  const uint32_t n = m.particle_count(), d = st->grid_dim, cells = d * d * d;
  const uint32_t k_max = m.params.max_neighbours;
  for (uint32_t c = 0; c <= cells; ++c) st->cell_start[c] = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const fx::Vec3 p{st->position[0][i], st->position[1][i], st->position[2][i]};
    st->cell[i] = cell_index(*st, centre, p);
    ++st->cell_start[st->cell[i] + 1];
  }
  for (uint32_t c = 0; c < cells; ++c) st->cell_start[c + 1] += st->cell_start[c];
  // Scatter in index order (stable), using cell_start[c] as the cursor, then
  // shift the cursors back to the starts.
  for (uint32_t i = 0; i < n; ++i) st->sorted[st->cell_start[st->cell[i]]++] = static_cast<uint16_t>(i);
  for (uint32_t c = cells; c > 0; --c) st->cell_start[c] = st->cell_start[c - 1];
  st->cell_start[0] = 0;

  const InvH ih = make_inv_h(m.params.h);
  for (uint32_t i = 0; i < n; ++i) {
    const fx::Vec3 pi{st->position[0][i], st->position[1][i], st->position[2][i]};
    const uint32_t c = st->cell[i];
    const int32_t cx = static_cast<int32_t>(c % d), cy = static_cast<int32_t>((c / d) % d),
                  cz = static_cast<int32_t>(c / (d * d));
    Neighbour* list = &st->neighbours[size_t{i} * k_max];
    uint32_t count = 0;
    for (int32_t z = cz - 1; z <= cz + 1; ++z) {
      if (z < 0 || z >= static_cast<int32_t>(d)) continue;
      for (int32_t y = cy - 1; y <= cy + 1; ++y) {
        if (y < 0 || y >= static_cast<int32_t>(d)) continue;
        for (int32_t x = cx - 1; x <= cx + 1; ++x) {
          if (x < 0 || x >= static_cast<int32_t>(d)) continue;
          const uint32_t cc = (static_cast<uint32_t>(z) * d + static_cast<uint32_t>(y)) * d + static_cast<uint32_t>(x);
          for (uint32_t k = st->cell_start[cc]; k < st->cell_start[cc + 1]; ++k) {
            const uint32_t j = st->sorted[k];
            if (j == i) continue;
            PairGeometry g;
            if (!pair_geometry(pi, {st->position[0][j], st->position[1][j], st->position[2][j]}, ih, &g)) continue;
            if (count == k_max) {
              ++st->stats.neighbour_overflow;
              continue;
            }
            list[count++] = {static_cast<uint16_t>(j), 0, g.s};
          }
        }
      }
    }
    st->neighbour_count[i] = static_cast<uint8_t>(count);
    st->stats.neighbour_pairs += count;
    if (count > st->stats.max_neighbour_count) st->stats.max_neighbour_count = count;
  }
}

void compute_density(SphState* st) {
  const uint32_t n = st->model->particle_count(), k_max = st->model->params.max_neighbours;
  for (uint32_t i = 0; i < n; ++i) {
    int64_t sum = int64_t{1} << 30;  // the particle itself: poly6(0) = 1
    const Neighbour* list = &st->neighbours[size_t{i} * k_max];
    for (uint32_t k = 0; k < st->neighbour_count[i]; ++k) sum += poly6(list[k].s);
    // At most 1 + 96 terms of at most 1.0: below 2^37 in Q30, 97 in Q8.24.
    st->density[i] = static_cast<Dens>(fx::round_shift(sum, 30 - kDensFracBits));
  }
}

}  // namespace sinew::sph
