#include "sph_grid.hpp"

#include "sim_core/fixed/wide.hpp"
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

// The forward neighbourhood of a cell in the half stencil: the sorted
// ranges of its own x-row after a particle (to own_end) and of up to four
// forward x-rows, (z, y+1) and (z+1, y-1..y+1).
struct ForwardRows {
  uint32_t from[4], to[4], rows = 0;
  uint32_t own_end = 0;
};

ForwardRows forward_rows(const SphState& st, uint32_t c) {
  const uint32_t d = st.grid_dim;
  const uint32_t* start = st.cell_start.data();
  const uint32_t cx = c % d, cy = (c / d) % d, cz = c / (d * d);
  const uint32_t xlo = cx > 0 ? cx - 1 : 0, xhi = cx + 1 < d ? cx + 1 : d - 1;
  ForwardRows r;
  const auto row = [&](uint32_t z, uint32_t y) {
    const uint32_t base = (z * d + y) * d;
    r.from[r.rows] = start[base + xlo];
    r.to[r.rows] = start[base + xhi + 1];
    r.rows += r.from[r.rows] != r.to[r.rows] ? 1u : 0u;
  };
  if (cy + 1 < d) row(cz, cy + 1);
  if (cz + 1 < d) {
    if (cy > 0) row(cz + 1, cy - 1);
    row(cz + 1, cy);
    if (cy + 1 < d) row(cz + 1, cy + 1);
  }
  r.own_end = start[(cz * d + cy) * d + xhi + 1];
  return r;
}

// One pair's sides, from pair_entry.
struct PairSides {
  uint32_t a, b;  // 1 where that side is inside the kernel
  uint32_t s_ab, s_ba;
  int32_t w_ab;  // poly6 seen from a (0 outside the kernel)
  // poly6 seen from b (0 outside the kernel).
  int32_t w_ba() const { return s_ba == s_ab ? w_ab : poly6(b != 0 ? s_ba : uint32_t{1} << 30); }
};

// Geometry as pair_geometry (sph_kernels.hpp) from a's side, d = x_a - x_b
// with every |d_c| < h, written to *e (particles i at a and j at b); b's
// side negates each rounded axis, plus one LSB where the axis rounded on an
// exact half (round_shift rounds halves up): round(-v) = -round(v) + [v on
// a half]. Both sides are exact whichever particle is a.
[[gnu::always_inline]] inline PairSides pair_entry(int64_t dx, int64_t dy, int64_t dz, int64_t inv, uint32_t i,
                                                   uint32_t j, SphPair* e) {
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
  // Unconditional store, kept by the caller when a side is inside the kernel.
  e->a = static_cast<uint16_t>(i);
  e->b = static_cast<uint16_t>(j);
  e->sides = static_cast<uint8_t>(side_a | (side_b << 1));
  e->half = static_cast<uint8_t>(hx | (hy << 1) | (hz << 2));
  e->reserved = 0;
  e->s_ab = static_cast<uint32_t>(s_ab);
  e->s_ba = static_cast<uint32_t>(s_ba);
  e->d[0] = static_cast<int32_t>(nx);
  e->d[1] = static_cast<int32_t>(ny);
  e->d[2] = static_cast<int32_t>(nz);
  return {side_a, side_b, e->s_ab, e->s_ba, poly6(static_cast<uint32_t>(side_a != 0 ? s_ab : kOne))};
}

// The half-stencil search of sph_grid.hpp, its pairs stored from `pairs`
// on. kBothSides: both particles of a pair take their count and density
// term at once (the search of the whole grid on one thread). Otherwise the
// scanning particle alone takes its own (a range of particles on a worker;
// the other sides are gathered afterwards, sph_grid.cpp).
template <bool kBothSides>
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

  // Every cell in order, each particle against its forward neighbourhood
  // (kBothSides; the counts and sums reset first).
  void run_grid() {
    const uint32_t* start = st_->cell_start.data();
    const uint32_t cells = st_->grid_dim * st_->grid_dim * st_->grid_dim;
    for (uint32_t c = 0; c < cells; ++c) {
      if (start[c] == start[c + 1]) continue;
      const ForwardRows r = forward_rows(*st_, c);  // shared by the cell's particles
      for (uint32_t p = start[c]; p < start[c + 1]; ++p) {
        // a's count and density sum stay in registers across its ranges.
        count_a_ = 0;
        dens_a_ = 0;
        scan_forward(p, r);
        const uint32_t i = sorted_[p];
        count_[i] = static_cast<uint16_t>(count_[i] + count_a_);
        dens_[i] += dens_a_;
      }
    }
  }

  // The sorted particles [p_begin, p_end) (not kBothSides): each one's own
  // count, density sum and run of pairs (run_first: pairs_[0] is entry
  // `first_entry` of the state's list).
  void run_particles(uint32_t p_begin, uint32_t p_end, uint32_t first_entry) {
    uint32_t cell = UINT32_MAX;
    ForwardRows r;
    for (uint32_t p = p_begin; p < p_end; ++p) {
      const uint32_t i = sorted_[p];
      if (st_->cell[i] != cell) {
        cell = st_->cell[i];
        r = forward_rows(*st_, cell);
      }
      count_a_ = 0;
      dens_a_ = 0;
      const uint32_t before = np_;
      scan_forward(p, r);
      count_[i] = static_cast<uint16_t>(count_a_);
      dens_[i] = (int64_t{1} << 30) + dens_a_;  // the particle itself: poly6(0) = 1
      st_->run_first[i] = first_entry + before;
      st_->run_count[i] = static_cast<uint16_t>(np_ - before);  // checked by the caller (overflowed)
    }
  }

 private:
  void scan_forward(uint32_t p, const ForwardRows& r) {
    scan(p, p + 1, r.own_end);
    for (uint32_t k = 0; k < r.rows; ++k) scan(p, r.from[k], r.to[k]);
  }

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

  void exact(uint32_t p, uint32_t q, uint32_t& np, uint32_t& count_a, int64_t& dens_a) {
    const uint32_t i = sorted_[p], j = sorted_[q];
    // Past the capacity the spare last entry takes the store (and the
    // substep falls back to the ordered lists).
    SphPair& e = pairs_[np < cap_ ? np : cap_];
    const PairSides sides =
        pair_entry(int64_t{x_[p]} - x_[q], int64_t{y_[p]} - y_[q], int64_t{z_[p]} - z_[q], inv_, i, j, &e);
    count_a += sides.a;
    dens_a += sides.w_ab;
    if constexpr (kBothSides) {
      count_[j] = static_cast<uint16_t>(count_[j] + sides.b);
      dens_[j] += sides.w_ba();
    }
    np += (sides.a | sides.b);
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

void search_serial(SphState* st) {
  const uint32_t cap = st->model->particle_count() * st->model->params.max_neighbours;
  reset_sums(st);
  st->gathered = false;
  PairSearch<true> search(st, st->pairs.data(), cap);
  search.run_grid();
  if (search.overflowed() || !lists_fit(st)) {
    ordered_lists(st);
    return;
  }
  st->pair_count = search.pairs();
}

// The candidate pairs (sph_grid.hpp): every pair closer than the reach
// when listed, tested afresh each substep until some particle, measured
// from the grid centre, has moved more than the slack from where it was.
// A pair missing from the list was at least the reach apart; both its
// particles have moved by at most the slack, so it is now at least
// reach - 2 slack >= h (1 + 2^-10) + 1 apart, outside the kernel from
// both sides (the coarse sphere test of PairSearch::scan rests on the same
// bound), as the full search would find it.
struct Reach {
  int64_t reach = 0;  // below 2h: a listed pair lies within two cells on every axis
  int64_t slack = 0;  // <= 0: no candidates (h too small for the bound)
};

Reach reach_of(fx::Len h) {
  const int64_t hh = h;
  Reach r;
  if (hh >= (int64_t{1} << 29)) return r;  // keeps reach^2 and the squared moves far inside int64
  r.reach = hh + hh / 4;
  const int64_t outer = hh + (hh + 1023) / 1024 + 1;  // >= h (1 + 2^-10) + 1
  r.slack = (r.reach - outer) / 2 - 1;
  return r;
}

// Whether the listed candidates still hold every pair inside the kernel.
bool candidates_hold(const SphState& st, fx::Vec3 centre) {
  if (!st.candidates_valid) return false;
  const Reach r = reach_of(st.model->params.h);
  const uint32_t n = st.model->particle_count();
  const int64_t shift[3] = {int64_t{centre.x} - st.candidate_centre.x, int64_t{centre.y} - st.candidate_centre.y,
                            int64_t{centre.z} - st.candidate_centre.z};
  const uint64_t limit = static_cast<uint64_t>(r.slack), limit2 = limit * limit;
  uint32_t far = 0;
  for (uint32_t i = 0; i < n; ++i) {
    uint64_t moved2 = 0;
    for (int a = 0; a < 3; ++a) {
      // |move| < 2^34: each component is capped just past the slack first.
      const uint64_t m = fx::magnitude(int64_t{st.position[a][i]} - st.candidate_origin[a][i] - shift[a]);
      const uint64_t capped = m < limit + 1 ? m : limit + 1;
      moved2 += capped * capped;
    }
    far |= static_cast<uint32_t>(moved2 > limit2);
  }
  return far == 0;
}

// Lists the candidates from the current positions (sorted into cells of h
// first): the half stencil of the search widened to two cells on every
// axis. False if they outgrow their room (then none are listed).
bool list_candidates(SphState* st, fx::Vec3 centre) {
  st->candidates_valid = false;
  const Reach r = reach_of(st->model->params.h);
  if (r.slack <= 0) return false;
  bin_and_sort(st, centre);
  const uint32_t d = st->grid_dim, cells = d * d * d;
  const uint32_t* start = st->cell_start.data();
  const fx::Len* const x = st->sorted_position[0].data();
  const fx::Len* const y = st->sorted_position[1].data();
  const fx::Len* const z = st->sorted_position[2].data();
  const uint16_t* const sorted = st->sorted.data();
  SphCandidate* const out = st->candidates.data();
  const uint32_t cap = static_cast<uint32_t>(st->candidates.size());
  const int64_t reach = r.reach, reach2 = reach * reach;
  uint32_t count = 0;
  for (uint32_t c = 0; c < cells; ++c) {
    if (start[c] == start[c + 1]) continue;
    const uint32_t cx = c % d, cy = (c / d) % d, cz = c / (d * d);
    const uint32_t xlo = cx >= 2 ? cx - 2 : 0, xhi = cx + 2 < d ? cx + 2 : d - 1;
    const uint32_t ylo = cy >= 2 ? cy - 2 : 0, yhi = cy + 2 < d ? cy + 2 : d - 1;
    // Forward rows: (z, y+1..y+2) and (z+1..z+2, y-2..y+2), x in [x-2, x+2].
    uint32_t from[12], to[12], rows = 0;
    const auto row = [&](uint32_t rz, uint32_t ry) {
      const uint32_t base = (rz * d + ry) * d;
      from[rows] = start[base + xlo];
      to[rows] = start[base + xhi + 1];
      rows += from[rows] != to[rows] ? 1u : 0u;
    };
    for (uint32_t ry = cy + 1; ry <= yhi; ++ry) row(cz, ry);
    for (uint32_t rz = cz + 1; rz <= cz + 2 && rz < d; ++rz)
      for (uint32_t ry = ylo; ry <= yhi; ++ry) row(rz, ry);
    const uint32_t own_end = start[(cz * d + cy) * d + xhi + 1];
    for (uint32_t p = start[c]; p < start[c + 1]; ++p) {
      st->candidate_first[sorted[p]] = count < cap ? count : cap;
      const int64_t xa = x[p], ya = y[p], za = z[p];
      const auto scan = [&](uint32_t lo, uint32_t hi) {
        for (uint32_t q = lo; q < hi; ++q) {
          const int64_t dx = x[q] - xa, dy = y[q] - ya, dz = z[q] - za;
          if (dx >= reach || dx <= -reach || dy >= reach || dy <= -reach || dz >= reach || dz <= -reach) continue;
          if (dx * dx + dy * dy + dz * dz >= reach2) continue;  // each square < 2^60.7
          if (count < cap) out[count] = {sorted[p], sorted[q]};
          ++count;
        }
      };
      scan(p + 1, own_end);
      for (uint32_t k = 0; k < rows; ++k) scan(from[k], to[k]);
      st->candidate_end[sorted[p]] = count < cap ? count : cap;
    }
  }
  if (count > cap) return false;
  const uint32_t n = st->model->particle_count();
  for (int a = 0; a < 3; ++a)
    for (uint32_t i = 0; i < n; ++i) st->candidate_origin[a][i] = st->position[a][i];
  st->candidate_centre = centre;
  st->candidate_count = count;
  st->candidates_valid = true;
  return true;
}

// The candidates' pairs inside the kernel, as PairSearch stores them (its
// box test, then pair_entry), one particle's run of candidates at a time
// (candidate_first / candidate_end). kBothSides: the other particle's count
// and density term too (the search on one thread); otherwise that side is
// gathered afterwards (search_gathered).
template <bool kBothSides>
class CandidateFilter {
 public:
  CandidateFilter(SphState* st, SphPair* pairs, uint32_t cap)
      : x_(st->position[0].data()),
        y_(st->position[1].data()),
        z_(st->position[2].data()),
        list_(st->candidates.data()),
        count_(st->neighbour_count.data()),
        dens_(st->density_sum.data()),
        pairs_(pairs),
        cap_(cap) {
    const InvH ih = make_inv_h(st->model->params.h);
    h_ = ih.h;
    inv_ = ih.inv;
    // At |d| >= h (1 + 2^-10) both sides are outside the kernel (PairSearch::scan's
    // coarse sphere test): such a pair adds nothing and is not stored.
    const int64_t outer = h_ + (h_ + 1023) / 1024 + 1;
    outer2_ = outer * outer;
  }

  uint32_t pairs() const { return np_; }
  bool overflowed() const { return np_ > cap_; }

  // Candidates [from, to), all of particle i as a: adds a's neighbours and
  // density terms to count_a and dens_a.
  void run(uint32_t i, uint32_t from, uint32_t to, uint32_t& count_a, int64_t& dens_a) {
    const int64_t h = h_;
    const uint64_t box = static_cast<uint64_t>(2 * h - 1);  // |d_c| <= h - 1 as one unsigned compare
    const auto in_box = [&](int64_t v) { return static_cast<uint32_t>(static_cast<uint64_t>(v + h - 1) < box); };
    const int64_t xi = x_[i], yi = y_[i], zi = z_[i];
    uint32_t np = np_;
    for (uint32_t k = from; k < to; ++k) {
      const uint32_t j = list_[k].b;
      const int64_t dx = xi - x_[j], dy = yi - y_[j], dz = zi - z_[j];
      if ((in_box(dx) & in_box(dy) & in_box(dz)) == 0) continue;
      if (dx * dx + dy * dy + dz * dz >= outer2_) continue;  // |d_c| < h < 2^29: no overflow
      // Past the capacity the spare last entry takes the store.
      const PairSides sides = pair_entry(dx, dy, dz, inv_, i, j, &pairs_[np < cap_ ? np : cap_]);
      count_a += sides.a;
      dens_a += sides.w_ab;
      if constexpr (kBothSides) {
        count_[j] = static_cast<uint16_t>(count_[j] + sides.b);
        dens_[j] += sides.w_ba();
      }
      np += sides.a | sides.b;
    }
    np_ = np;
  }

 private:
  const fx::Len *x_, *y_, *z_;
  const SphCandidate* list_;
  uint16_t* count_;
  int64_t* dens_;
  SphPair* pairs_;
  uint32_t cap_;
  uint32_t np_ = 0;
  int64_t h_ = 0, inv_ = 0, outer2_ = 0;
};

// Substeps without candidates after a list outgrew its room: listing them
// costs about one full search, so a crowded joint is not made to pay it
// every substep.
constexpr uint32_t kCandidatePause = 64;

// Whether this substep's search may take the candidates: listed afresh
// when some particle has moved past the slack (or none are listed), left
// off while paused.
bool candidates_ready(SphState* st, fx::Vec3 centre) {
  if (st->candidate_pause > 0) --st->candidate_pause;
  if (st->candidate_pause == 0 && !candidates_hold(*st, centre)) {
    ++st->stats.candidate_builds;
    if (!list_candidates(st, centre)) st->candidate_pause = kCandidatePause;
  }
  return st->candidates_valid && st->candidate_pause == 0;
}

// The search on one thread through the candidates: the pairs, counts and
// sums of search_serial, word for word.
void search_listed(SphState* st, fx::Vec3 centre) {
  const uint32_t n = st->model->particle_count();
  const uint32_t cap = n * st->model->params.max_neighbours;
  reset_sums(st);
  st->gathered = false;
  CandidateFilter<true> filter(st, st->pairs.data(), cap);
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t count_a = 0;
    int64_t dens_a = 0;
    filter.run(i, st->candidate_first[i], st->candidate_end[i], count_a, dens_a);
    st->neighbour_count[i] = static_cast<uint16_t>(st->neighbour_count[i] + count_a);
    st->density_sum[i] += dens_a;
  }
  if (filter.overflowed() || !lists_fit(st)) {
    bin_and_sort(st, centre);  // the ordered lists read this substep's cells
    ordered_lists(st);
    return;
  }
  st->pair_count = filter.pairs();
}

// The search over the workers. Each range of sorted particles searches its
// particles' forward neighbourhoods and keeps their own counts, density
// sums and runs of pairs, in entries of its own: a range of r particles
// starting at sorted index p0 from entry p0 (max_neighbours + 1), room for
// max_neighbours pairs per particle and the spare. Then the pairs are
// listed by b (a counting sort, on the calling thread) and every particle
// gathers its b-side counts and density terms. Integer sums: the words of
// the search on one thread. False if a range found more pairs than its
// room (possible only where many pairs have one side just outside the
// kernel): then the caller searches on one thread, the same pairs.
// With candidates, the ranges are of particle indices, each particle's run
// its candidates as a.
bool search_gathered(SphState* st, fx::Vec3 centre, const layer::Workers* workers, bool listed) {
  const uint32_t n = st->model->particle_count(), k_max = st->model->params.max_neighbours;
  const uint32_t overflowed = layer::run_ranges_summed(workers, n, [&](uint32_t begin, uint32_t end) {
    const uint32_t first = begin * (k_max + 1);
    if (!listed) {
      PairSearch<false> search(st, st->pairs.data() + first, (end - begin) * k_max);
      search.run_particles(begin, end, first);
      return search.overflowed() ? 1u : 0u;
    }
    CandidateFilter<false> filter(st, st->pairs.data() + first, (end - begin) * k_max);
    for (uint32_t i = begin; i < end; ++i) {
      uint32_t count_a = 0;
      int64_t dens_a = 0;
      const uint32_t before = filter.pairs();
      filter.run(i, st->candidate_first[i], st->candidate_end[i], count_a, dens_a);
      st->neighbour_count[i] = static_cast<uint16_t>(count_a);
      st->density_sum[i] = (int64_t{1} << 30) + dens_a;  // the particle itself: poly6(0) = 1
      st->run_first[i] = first + before;
      st->run_count[i] = static_cast<uint16_t>(filter.pairs() - before);  // checked below (overflowed)
    }
    return filter.overflowed() ? 1u : 0u;
  });
  if (overflowed != 0) return false;
  // Pairs by b: counts, inclusive prefix sums (b_offset[j] the end of j's
  // list), then filled from each end down (b_offset[j] its start).
  uint32_t* const offset = st->b_offset.data();
  const SphPair* const pairs = st->pairs.data();
  for (uint32_t j = 0; j <= n; ++j) offset[j] = 0;
  uint32_t total = 0;
  for (uint32_t i = 0; i < n; ++i) {
    total += st->run_count[i];
    for (uint32_t k = st->run_first[i]; k < st->run_first[i] + st->run_count[i]; ++k) ++offset[pairs[k].b];
  }
  for (uint32_t j = 1; j < n; ++j) offset[j] += offset[j - 1];
  offset[n] = total;
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t k = st->run_first[i]; k < st->run_first[i] + st->run_count[i]; ++k)
      st->b_pair[--offset[pairs[k].b]] = k;
  // b's side of each pair: its count and poly6 term (0 outside the kernel).
  layer::run_ranges_summed(workers, n, [&](uint32_t begin, uint32_t end) {
    constexpr uint32_t kOne = uint32_t{1} << 30;
    for (uint32_t j = begin; j < end; ++j) {
      uint32_t count = 0;
      int64_t dens = 0;
      for (uint32_t m = offset[j]; m < offset[j + 1]; ++m) {
        const SphPair& e = pairs[st->b_pair[m]];
        const uint32_t side_b = (e.sides >> 1) & 1u;
        count += side_b;
        dens += poly6(side_b != 0 ? e.s_ba : kOne);
      }
      st->neighbour_count[j] = static_cast<uint16_t>(st->neighbour_count[j] + count);
      st->density_sum[j] += dens;
    }
    return 0u;
  });
  if (!lists_fit(st)) {
    st->gathered = false;
    if (listed) bin_and_sort(st, centre);  // the ordered lists read this substep's cells
    ordered_lists(st);
    return true;
  }
  st->pair_count = total;
  st->gathered = true;
  return true;
}

}  // namespace

void build_neighbours(SphState* st, fx::Vec3 centre, const layer::Workers* workers) {
  // The same threshold as layer::run_ranges: below it waking the workers
  // costs more than the search; every search gives the step the same
  // words (sph_determinism_test compares them for 1 to 7 workers).
  const bool spread = workers != nullptr && workers->run != nullptr && workers->parts > 1 &&
                      st->model->particle_count() >= 2 * layer::kMinPerLoop;
  if (candidates_ready(st, centre)) {
    if (spread && search_gathered(st, centre, workers, true)) return;
    return search_listed(st, centre);
  }
  bin_and_sort(st, centre);
  if (spread && search_gathered(st, centre, workers, false)) return;
  search_serial(st);
}

void sort_into_cells(SphState* st, fx::Vec3 centre) { bin_and_sort(st, centre); }

void compute_density(SphState* st) {
  const uint32_t n = st->model->particle_count();
  // At most 1 + 96 terms of at most 1.0: below 2^37 in Q30, 97 in Q8.24.
  for (uint32_t i = 0; i < n; ++i)
    st->density[i] = static_cast<Dens>(fx::round_shift(st->density_sum[i], 30 - kDensFracBits));
}

}  // namespace sinew::sph
