// Neighbour search on a uniform grid of cell size h centred on the joint,
// once per substep:
//   1. the cell of every particle (clamped into the grid's border cells) and
//      a counting sort by cell, stable, into CSR ranges (cell_start, sorted);
//   2. a half stencil: each particle meets the later particles of its own
//      x-row of three cells and the full x-rows (z, y+1), (z+1, y-1..y+1),
//      five contiguous ranges of the sorted positions, so every pair of
//      particles in neighbouring cells is examined once. Its geometry is
//      computed once and gives both sides exactly (SphPair), and both
//      particles' poly6 density sums take their term at once.
// The result equals per-particle lists over the 27 neighbouring cells, in
// cell then index order, cut at max_neighbours: integer sums are the same in
// any order. Only when some list would overflow max_neighbours does the cut
// depend on that order; that substep rebuilds the pairs from the ordered
// per-particle scan (one side per pair) so the same neighbours are dropped.
//
// The half stencil is not walked every substep: a list of
// candidate pairs, every pair closer than 1.25 h, is made by the same
// walk widened to two cells, and each substep tests only those, until a
// particle has moved more than the list's slack (about h / 8, measured
// from the grid centre, so the arm's own motion does not count) since it
// was made. The bound that makes this exact is in sph_grid.cpp; the pairs,
// counts and sums are the full search's (sph_equivalence_test and
// sph_determinism_test compare them). Fallbacks: a list that outgrows its
// room (n x max_neighbours) pauses the candidates for 64 substeps. Over the
// workers each particle's run of candidates (candidate_first/end) is
// filtered by the range it falls in, then gathered as below.
//
// Over the workers (two parts or more, 128 particles or more), each range of
// sorted particles searches its particles' forward neighbourhoods and keeps
// their own counts, density sums and runs of pairs in entries of its own;
// the pairs are then listed by their second particle and every particle
// gathers that side (SphState::gathered), its pair terms too
// (sph_step.cpp). The pairs, counts and sums are those of the search on one
// thread, for any number of parts.
#pragma once

#include "sim_core/layer/workers.hpp"
#include "sph_state.hpp"

namespace sinew::sph {

// Pairs, neighbour counts and density sums for the current positions; fills
// stats. workers: null or the threads the search may spread over.
void build_neighbours(SphState* state, fx::Vec3 centre, const layer::Workers* workers = nullptr);

// The counting sort of step 1 alone (cell, cell_start, sorted,
// sorted_position), for readers of the cells outside the search.
void sort_into_cells(SphState* state, fx::Vec3 centre);

// Density (poly6, self included) of every particle from the density sums.
void compute_density(SphState* state);

// Linear cell index of a position (clamped into the grid).
uint32_t cell_index(const SphState& state, fx::Vec3 centre, fx::Vec3 p);

}  // namespace sinew::sph
