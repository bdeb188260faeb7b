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

// Density (poly6, self included) of every particle from the density sums.
void compute_density(SphState* state);

// Linear cell index of a position (clamped into the grid).
uint32_t cell_index(const SphState& state, fx::Vec3 centre, fx::Vec3 p);

}  // namespace sinew::sph
