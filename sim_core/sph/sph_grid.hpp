// Neighbour search on a uniform grid of cell size h centred on the joint:
// a counting sort by cell (stable, so particles keep index order within a
// cell) then, per particle, the 27 surrounding cells in a fixed order. The
// order of every list is a pure function of the positions: no hashing, no
// pointers. Particles outside the grid are clamped into its border cells
// (still exact: every candidate's distance is checked).
#pragma once

#include "sph_state.hpp"

namespace sinew::sph {

// Builds state->neighbours for the current positions; fills stats.
void build_neighbours(SphState* state, fx::Vec3 centre);

// Density (poly6, self included) of every particle from its neighbour list.
void compute_density(SphState* state);

// Linear cell index of a position (clamped into the grid).
uint32_t cell_index(const SphState& state, fx::Vec3 centre, fx::Vec3 p);

}  // namespace sinew::sph
