#include "sph_grid.hpp"

#include "sim_core/layer/range_totals.hpp"
#include "sph_kernels.hpp"

namespace sinew::sph {
namespace {

// floor(off / h) clamped into [0, d - 1], off = p - (centre - grid_radius),
// without a division per particle.
struct AxisBinner {
  int64_t h = 0;
  int64_t inv = 0;    // round(2^50 / h)
  int64_t end = 0;    // d x h: offsets at or past it clamp into the last cell
  uint32_t last = 0;  // d - 1
};

AxisBinner make_binner(const SphState& st) {
  const InvH ih = make_inv_h(st.model->params.h);
  return {ih.h, ih.inv, int64_t{st.grid_dim} * ih.h, st.grid_dim - 1};
}

uint32_t bin(const AxisBinner& b, int64_t off) {
  if (off <= 0) return 0;
  if (off >= b.end) return b.last;
  // 0 < off < 64 h: off x inv < 2^57, and off x inv / 2^50 is off / h within
  // 2^-13 (|inv - 2^50 / h| <= 1/2), so its floor is floor(off / h) or one
  // off it; one comparison each way makes it exact.
  int64_t q = (off * b.inv) >> 50;
  if (q * b.h > off)
    --q;
  else if ((q + 1) * b.h <= off)
    ++q;
  return static_cast<uint32_t>(q);
}

uint32_t cell_of(const AxisBinner& b, uint32_t d, const int64_t origin[3], int32_t x, int32_t y, int32_t z) {
  return (bin(b, int64_t{z} - origin[2]) * d + bin(b, int64_t{y} - origin[1])) * d + bin(b, int64_t{x} - origin[0]);
}

// Cells and the stable counting sort into CSR ranges; positions copied in
// sorted order so the pair search reads contiguous memory.
void bin_and_sort(SphState* st, fx::Vec3 centre) {
  const SphModel& m = *st->model;
  const uint32_t n = m.particle_count(), d = st->grid_dim, cells = d * d * d;
  const AxisBinner b = make_binner(*st);
  const int64_t r = m.params.grid_radius;
  const int64_t origin[3] = {int64_t{centre.x} - r, int64_t{centre.y} - r, int64_t{centre.z} - r};
  uint32_t* start = st->cell_start.data();
  for (uint32_t c = 0; c <= cells; ++c) start[c] = 0;
  for (uint32_t i = 0; i < n; ++i) {
    st->cell[i] = cell_of(b, d, origin, st->position[0][i], st->position[1][i], st->position[2][i]);
    ++start[st->cell[i] + 1];
  }
  for (uint32_t c = 0; c < cells; ++c) start[c + 1] += start[c];
  // Scatter in index order (stable), using start[c] as the cursor, then
  // shift the cursors back to the starts.
  for (uint32_t i = 0; i < n; ++i) st->sorted[start[st->cell[i]]++] = static_cast<uint16_t>(i);
  for (uint32_t c = cells; c > 0; --c) start[c] = start[c - 1];
  start[0] = 0;
  for (int a = 0; a < 3; ++a)
    for (uint32_t k = 0; k < n; ++k) st->sorted_position[a][k] = st->position[a][st->sorted[k]];
}

// The half-stencil search of sph_grid.hpp over the cells of the layers
// [z_begin, z_end), its pairs stored from `pairs` on. Writes the counts and
// density sums of the layers' particles and of the next layer's (the
// stencil's forward rows); reset_sums clears them first.
class PairSearch {
 public:
  static constexpr uint32_t kChunk = 64;

  // cap: the pairs this search may keep; it stores one entry past them
  // (pairs[cap], the spare) whatever it finds.
  PairSearch(SphState* st, SphPair* pairs, uint32_t cap)
      : st_(st),
        x_(st->sorted_position[0].data()),
        y_(st->sorted_position[1].data()),
        z_(st->sorted_position[2].data()),
        sorted_(st->sorted.data()),
        count_(st->neighbour_count.data()),
        dens_(st->density_sum.data()),
        pairs_(pairs),
        cap_(cap) {
    const InvH ih = make_inv_h(st->model->params.h);
    h_ = ih.h;
    inv_ = ih.inv;
    // Coarse offsets dx >> shift_ below 2^14 in magnitude inside the box;
    // outside_ = h^2 (1 + 2^-10) >> 2 shift_, rounded up (see scan).
    uint32_t bits = 0;
    while (bits < 32 && (int64_t{1} << bits) <= ih.h) ++bits;  // h < 2^bits
    shift_ = bits > 14 ? bits - 14 : 0;
    const int64_t h2 = int64_t{ih.h} * ih.h;
    outside_ = static_cast<uint32_t>(((h2 + (h2 >> 10) + 1) >> (2 * shift_)) + 1);
  }

  // The pairs found (all kept unless beyond cap).
  uint32_t pairs() const { return np_; }
  bool overflowed() const { return np_ > cap_; }

  void run(uint32_t z_begin, uint32_t z_end) {
    const uint32_t d = st_->grid_dim;
    const uint32_t* start = st_->cell_start.data();
    for (uint32_t cz = z_begin; cz < z_end; ++cz)
      for (uint32_t cy = 0; cy < d; ++cy)
        for (uint32_t cx = 0; cx < d; ++cx) {
          const uint32_t c = (cz * d + cy) * d + cx;
          if (start[c] == start[c + 1]) continue;
          const uint32_t xlo = cx > 0 ? cx - 1 : 0, xhi = cx + 1 < d ? cx + 1 : d - 1;
          // The forward rows' ranges (x from xlo to xhi), shared by the cell's particles.
          uint32_t from[4], to[4], rows = 0;
          const auto row = [&](uint32_t z, uint32_t y) {
            const uint32_t base = (z * d + y) * d;
            from[rows] = start[base + xlo];
            to[rows] = start[base + xhi + 1];
            rows += from[rows] != to[rows] ? 1u : 0u;
          };
          if (cy + 1 < d) row(cz, cy + 1);
          if (cz + 1 < d) {
            if (cy > 0) row(cz + 1, cy - 1);
            row(cz + 1, cy);
            if (cy + 1 < d) row(cz + 1, cy + 1);
          }
          const uint32_t own_end = start[(cz * d + cy) * d + xhi + 1];
          for (uint32_t p = start[c]; p < start[c + 1]; ++p) {
            // a's count and density sum stay in registers across its ranges.
            count_a_ = 0;
            dens_a_ = 0;
            scan(p, p + 1, own_end);
            for (uint32_t k = 0; k < rows; ++k) scan(p, from[k], to[k]);
            const uint32_t i = sorted_[p];
            count_[i] = static_cast<uint16_t>(count_[i] + count_a_);
            dens_[i] += dens_a_;
          }
        }
  }

 private:
  static int32_t clamp_len(int64_t v) {
    return static_cast<int32_t>(v < INT32_MIN ? INT32_MIN : (v > INT32_MAX ? INT32_MAX : v));
  }

  // A lower bound of |dx| / 2^shift_ from the coarse offset e = dx >> shift_
  // (a floor): e for e >= 0, -e - 1 = ~e below.
  static uint32_t coarse(int32_t a, int32_t b, uint32_t shift) {
    // Wrapping difference: the true dx wherever the box test holds.
    const int32_t e = static_cast<int32_t>(static_cast<uint32_t>(a) - static_cast<uint32_t>(b)) >> shift;
    return static_cast<uint32_t>(e ^ (e >> 31));
  }

  // Particle sorted[p] against sorted[from..to), by chunks: first two exact
  // filters in 32-bit lanes (a loop the compiler vectorises), the survivors
  // compacted without branches, then the exact geometry of those.
  //   box:    |x_a - x_b| < h on every axis, as compares against bounds
  //           clamped into the Len range (x_b in [x_a - h + 1, x_a + h - 1]);
  //   sphere: sum of the coarse lower bounds squared (each < 2^14, so the
  //           sum fits 32 bits) at least outside_ means |r_ab| >= h (1 +
  //           2^-10), and then both sides' q^2 round to >= 1: the rounding
  //           of pair_geometry moves q^2 by less than 2^-16.
  void scan(uint32_t p, uint32_t from, uint32_t to) {
    const int64_t h = h_;
    const int32_t xa = x_[p], ya = y_[p], za = z_[p];
    const int32_t lo[3] = {clamp_len(int64_t{xa} - h + 1), clamp_len(int64_t{ya} - h + 1),
                           clamp_len(int64_t{za} - h + 1)};
    const int32_t hi[3] = {clamp_len(int64_t{xa} + h - 1), clamp_len(int64_t{ya} + h - 1),
                           clamp_len(int64_t{za} + h - 1)};
    const uint32_t shift = shift_, outside = outside_;
    for (uint32_t base = from; base < to; base += kChunk) {
      const uint32_t len = to - base < kChunk ? to - base : kChunk;
      const fx::Len *xs = x_ + base, *ys = y_ + base, *zs = z_ + base;
      uint8_t inside[kChunk];
      for (uint32_t k = 0; k < len; ++k) {
        const uint32_t box = (xs[k] >= lo[0]) & (xs[k] <= hi[0]) & (ys[k] >= lo[1]) & (ys[k] <= hi[1]) &
                             (zs[k] >= lo[2]) & (zs[k] <= hi[2]);
        const uint32_t cx = coarse(xa, xs[k], shift), cy = coarse(ya, ys[k], shift), cz = coarse(za, zs[k], shift);
        inside[k] = static_cast<uint8_t>(box & (cx * cx + cy * cy + cz * cz < outside));
      }
      uint8_t index[kChunk];
      uint32_t m = 0;
      for (uint32_t k = 0; k < len; ++k) {
        index[m] = static_cast<uint8_t>(k);
        m += inside[k];
      }
      // Locals across the exact calls: stores through the pair and count
      // pointers cannot alias them, so they stay in registers.
      uint32_t np = np_, count_a = count_a_;
      int64_t dens_a = dens_a_;
      for (uint32_t t = 0; t < m; ++t) exact(p, base + index[t], np, count_a, dens_a);
      np_ = np;
      count_a_ = count_a;
      dens_a_ = dens_a;
    }
  }

  // Geometry as pair_geometry (sph_kernels.hpp) from a's side, for a pair
  // inside the box; b's side negates each rounded axis, plus one LSB where
  // the axis rounded on an exact half (round_shift rounds halves up):
  // round(-v) = -round(v) + [v on a half].
  void exact(uint32_t p, uint32_t q, uint32_t& np, uint32_t& count_a, int64_t& dens_a) {
    const int64_t inv = inv_;
    const int64_t dx = int64_t{x_[p]} - x_[q], dy = int64_t{y_[p]} - y_[q], dz = int64_t{z_[p]} - z_[q];
    // |d| < h < 2^31 and inv < 2^50 / h + 1: the products stay below 2^50.
    const int64_t px = dx * inv, py = dy * inv, pz = dz * inv;
    const int64_t nx = fx::round_shift(px, 20), ny = fx::round_shift(py, 20), nz = fx::round_shift(pz, 20);
    const int64_t sum = nx * nx + ny * ny + nz * nz;
    constexpr int64_t kLow = (int64_t{1} << 20) - 1, kHalf = int64_t{1} << 19;
    const int64_t hx = (px & kLow) == kHalf, hy = (py & kLow) == kHalf, hz = (pz & kLow) == kHalf;
    const int64_t s_ab = fx::round_shift(sum, 30);
    int64_t s_ba = s_ab;
    if ((hx | hy | hz) != 0)  // rare: an exact half
      // (-n + t)^2 = n^2 + t (1 - 2 n) for t in {0, 1}.
      s_ba = fx::round_shift(sum + hx * (1 - 2 * nx) + hy * (1 - 2 * ny) + hz * (1 - 2 * nz), 30);
    constexpr int64_t kOne = int64_t{1} << 30;
    const uint32_t side_a = s_ab < kOne ? 1u : 0u, side_b = s_ba < kOne ? 1u : 0u;
    const uint32_t i = sorted_[p], j = sorted_[q];
    count_a += side_a;
    count_[j] = static_cast<uint16_t>(count_[j] + side_b);
    const int32_t w_ab = poly6(static_cast<uint32_t>(side_a != 0 ? s_ab : kOne));
    dens_a += w_ab;
    dens_[j] += s_ba == s_ab ? w_ab : poly6(static_cast<uint32_t>(side_b != 0 ? s_ba : kOne));
    // Unconditional store, kept when a side is inside the kernel; past the
    // capacity the spare last entry takes it (and the substep falls back to
    // the ordered lists).
    SphPair& e = pairs_[np < cap_ ? np : cap_];
    e.a = static_cast<uint16_t>(i);
    e.b = static_cast<uint16_t>(j);
    e.sides = static_cast<uint8_t>(side_a | (side_b << 1));
    e.half = static_cast<uint8_t>(hx | (hy << 1) | (hz << 2));
    e.reserved = 0;
    e.s_ab = static_cast<uint32_t>(s_ab);
    e.s_ba = static_cast<uint32_t>(s_ba);
    e.d[0] = static_cast<int32_t>(nx);
    e.d[1] = static_cast<int32_t>(ny);
    e.d[2] = static_cast<int32_t>(nz);
    np += (side_a | side_b);
  }

  SphState* st_;
  const fx::Len *x_, *y_, *z_;
  const uint16_t* sorted_;
  uint16_t* count_;
  int64_t* dens_;
  SphPair* pairs_;
  uint32_t cap_;
  uint32_t np_ = 0;
  int64_t h_ = 0, inv_ = 0;
  uint32_t shift_ = 0, outside_ = 0;  // the coarse sphere test of scan
  uint32_t count_a_ = 0;              // the scanning particle's neighbours and density terms so far
  int64_t dens_a_ = 0;
};

// The per-particle scan of the 27 cells in cell then index order, cut at
// max_neighbours: the order decides which neighbours an overflowing list
// drops. One side per pair (b in a's list), as many pairs as list entries.
void ordered_lists(SphState* st) {
  const SphModel& m = *st->model;
  const uint32_t n = m.particle_count(), d = st->grid_dim;
  const uint32_t k_max = m.params.max_neighbours;
  const InvH ih = make_inv_h(m.params.h);
  uint32_t np = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const fx::Vec3 pi{st->position[0][i], st->position[1][i], st->position[2][i]};
    const uint32_t c = st->cell[i];
    const int32_t cx = static_cast<int32_t>(c % d), cy = static_cast<int32_t>((c / d) % d),
                  cz = static_cast<int32_t>(c / (d * d));
    uint32_t count = 0;
    int64_t sum = int64_t{1} << 30;  // the particle itself: poly6(0) = 1
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
            ++count;
            sum += poly6(g.s);
            st->pairs[np++] = {static_cast<uint16_t>(i), static_cast<uint16_t>(j), 1, 0, 0, g.s, g.s,
                               {g.d.x, g.d.y, g.d.z}};
          }
        }
      }
    }
    st->neighbour_count[i] = static_cast<uint16_t>(count);
    st->density_sum[i] = sum;
    st->stats.neighbour_pairs += count;
    if (count > st->stats.max_neighbour_count) st->stats.max_neighbour_count = count;
  }
  st->pair_count = np;
}

}  // namespace

uint32_t cell_index(const SphState& st, fx::Vec3 centre, fx::Vec3 p) {
  const int64_t r = st.model->params.grid_radius;
  const int64_t origin[3] = {int64_t{centre.x} - r, int64_t{centre.y} - r, int64_t{centre.z} - r};
  return cell_of(make_binner(st), st.grid_dim, origin, p.x, p.y, p.z);
}

namespace {

void reset_sums(SphState* st) {
  for (uint32_t i = 0; i < st->model->particle_count(); ++i) {
    st->neighbour_count[i] = 0;
    st->density_sum[i] = int64_t{1} << 30;  // the particle itself: poly6(0) = 1
  }
}

// After a search that kept every pair: false if some list exceeds
// max_neighbours (then the ordered lists decide which neighbours drop),
// else the stats taken.
bool lists_fit(SphState* st) {
  const uint32_t n = st->model->particle_count(), k_max = st->model->params.max_neighbours;
  bool overflow = false;
  uint32_t total = 0, largest = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t c = st->neighbour_count[i];
    overflow = overflow || c > k_max;
    total += c;
    largest = c > largest ? c : largest;
  }
  if (overflow) return false;
  st->stats.neighbour_pairs += total;
  if (largest > st->stats.max_neighbour_count) st->stats.max_neighbour_count = largest;
  return true;
}

void one_segment(SphState* st, uint32_t pairs) {
  st->pair_count = pairs;
  st->segments = 1;
  st->segment_begin[0] = 0;
  st->segment_pairs[0] = pairs;
}

void search_serial(SphState* st) {
  const uint32_t cap = st->model->particle_count() * st->model->params.max_neighbours;
  reset_sums(st);
  PairSearch search(st, st->pairs.data(), cap);
  search.run(0, st->grid_dim);
  if (search.overflowed() || !lists_fit(st)) {
    ordered_lists(st);
    one_segment(st, st->pair_count);
    return;
  }
  one_segment(st, search.pairs());
}

// The first sorted particle of cell layer z.
uint32_t layer_first(const SphState& st, uint32_t z) { return st.cell_start[size_t{z} * st.grid_dim * st.grid_dim]; }

// Slabs of whole layers, up to two per part, each holding about the same
// number of particles and at least one layer; 1 if fewer than 4 (then one
// colour would have a single slab: nothing to share).
uint32_t split_regions(SphState* st, uint32_t parts) {
  const uint32_t d = st->grid_dim, n = st->model->particle_count();
  uint32_t regions = 2 * parts;
  if (regions > d) regions = d;
  if (regions > kMaxRegions) regions = kMaxRegions;
  if (regions < 4) return 1;
  uint32_t* layer = st->region_layer.data();
  layer[0] = 0;
  for (uint32_t r = 1; r < regions; ++r) {
    uint32_t z = layer[r - 1] + 1;
    const uint64_t wanted = uint64_t{n} * r / regions;
    while (z < d - (regions - r) && layer_first(*st, z) < wanted) ++z;
    layer[r] = z;
  }
  layer[regions] = d;
  return regions;
}

// The search over the workers, slab by slab: a slab's search writes the
// sums of its own layers and of the layer after it, so slabs of one colour
// (even, then odd) never write the same particle and run at once; integer
// sums and counts come out the same in any order. Segment r starts at the
// slab's first particle x max_neighbours (plus r spares before it), so it
// may keep max_neighbours pairs per particle of the slab. False if a slab
// found more (then nothing is kept and the caller searches on one thread:
// the same pairs).
bool search_regions(SphState* st, const layer::Workers* workers, uint32_t regions) {
  const uint32_t k_max = st->model->params.max_neighbours;
  reset_sums(st);
  uint32_t overflowed = 0;
  for (uint32_t colour = 0; colour < 2; ++colour) {
    const uint32_t slabs = (regions - colour + 1) / 2;
    overflowed += layer::run_heavy_ranges_summed(workers, slabs, [&](uint32_t begin, uint32_t end) {
      uint32_t over = 0;
      for (uint32_t k = begin; k < end; ++k) {
        const uint32_t r = 2 * k + colour;
        const uint32_t first = layer_first(*st, st->region_layer[r]);
        const uint32_t last = layer_first(*st, st->region_layer[r + 1]);  // cell_start[cells] = n past the grid
        const uint32_t base = first * k_max + r;
        PairSearch search(st, st->pairs.data() + base, (last - first) * k_max);
        search.run(st->region_layer[r], st->region_layer[r + 1]);
        st->segment_begin[r] = base;
        st->segment_pairs[r] = search.pairs();
        over += search.overflowed() ? 1u : 0u;
      }
      return over;
    });
  }
  if (overflowed != 0) return false;
  if (!lists_fit(st)) {
    ordered_lists(st);
    one_segment(st, st->pair_count);
    return true;
  }
  uint32_t total = 0;
  for (uint32_t r = 0; r < regions; ++r) total += st->segment_pairs[r];
  st->pair_count = total;
  st->segments = regions;
  return true;
}

}  // namespace

void build_neighbours(SphState* st, fx::Vec3 centre, const layer::Workers* workers) {
  bin_and_sort(st, centre);
  const uint32_t parts = workers != nullptr && workers->run != nullptr ? workers->parts : 1;
  const uint32_t regions = parts > 1 ? split_regions(st, parts) : 1;
  if (regions > 1 && search_regions(st, workers, regions)) return;
  search_serial(st);
}

void compute_density(SphState* st) {
  const uint32_t n = st->model->particle_count();
  // At most 1 + 96 terms of at most 1.0: below 2^37 in Q30, 97 in Q8.24.
  for (uint32_t i = 0; i < n; ++i)
    st->density[i] = static_cast<Dens>(fx::round_shift(st->density_sum[i], 30 - kDensFracBits));
}

}  // namespace sinew::sph
