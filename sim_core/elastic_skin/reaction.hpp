// Reaction constraints (LEMAN §3, §5.4, §6.11) with the fat layer (§5.6):
// each skin vertex's fat point p = v - fat * n (n: the anchor normal, or
// with solver.fat_normal = kSurface the skin mesh's normal of the last
// estimate_surface_normals, surface_normals.hpp) is
// inside-tested against every active primitive; a point inside is moved out
// along the primitive's gradient (Newton steps on F), the same displacement
// is applied to the skin vertex. Only the normal component changes, so the
// skin stays free to slide tangentially. `gain` < 1 removes that fraction
// of the penetration (first-order critically damped approach, no overshoot).
#pragma once

#include "sim_core/layer/workers.hpp"
#include "sim_core/muscle/muscle_state.hpp"
#include "skin_state.hpp"

namespace sinew::elastic_skin {

// Over the moving vertices; returns the number moved.
uint32_t apply_reaction_constraints(const SkinModel& model, const muscle::MuscleState& muscles, fx::Unit gain,
                                    SkinState* s, const layer::Workers* workers = nullptr);

// Dynamic mode: the vertices whose fat point lies within reach of an
// active primitive (inside its bounding sphere, or any point for a
// primitive without one), written in index order to s->weight (scratch
// between substeps); returns their count. A vertex left out is one no
// reaction pass moves: the passes move only listed vertices and the
// primitives stay put within a substep, so it stays out of reach.
uint32_t list_reaction_candidates(const SkinModel& model, const muscle::MuscleState& muscles, SkinState* s);

// Dynamic mode (LEMAN §3, §6.11): one Gauss-Seidel pass over the first
// `candidates` vertices listed by list_reaction_candidates; each primitive
// in turn moves the fat point out by its whole penetration and the vertex
// with it, and the vertex's velocity loses only its inward normal
// component (along the move): the point slides tangentially. `fine`
// (Q28.36) follows the move. Returns the number of vertices moved.
uint32_t apply_sliding_reactions(const SkinModel& model, const muscle::MuscleState& muscles, uint32_t candidates,
                                 SkinState* s);

// Relaxation integrator (surface_relaxation.hpp): for each of the first
// `candidates` vertices listed in s->weight, LEMAN §6.11's constraint
// gradient and depth: s->reaction_normal the unit gradient (Q2.30) of the
// first active primitive its fat point (from s->position) is inside, at
// that point, and s->reaction_floor the length of the move that takes the
// point out of every primitive (primitives in order, each from where the
// last left it), Q28.36; both zero outside every primitive. Returns the
// number of vertices inside.
uint32_t reaction_moves(const SkinModel& model, const muscle::MuscleState& muscles, uint32_t candidates, SkinState* s);

// Fat thickness of vertex v: its own plus the solver's global one (Len).
fx::Len fat_of(const SkinModel& model, uint32_t v);

// Static mode, once a step after the anchors are mapped: each moving
// vertex's fat point offset along the step's anchor normal, so the rounds' reaction passes and
// the final count subtract it instead of forming it. With solver.fat_normal
// = kSurface (the direction changes round by round) it leaves the offsets
// unset and the passes form them as before.
void place_fat_points(const SkinModel& model, SkinState* s, const layer::Workers* workers = nullptr);

// The moving vertices' fat points (SkinState::moving_vertex) still inside
// an active primitive by more than `tolerance` (Q2.30 on the
// inside/outside function: F < 1 - tolerance).
uint32_t count_inside(const SkinModel& model, const muscle::MuscleState& muscles, fx::Unit tolerance,
                      const SkinState& s, const layer::Workers* workers = nullptr);

// The same over `count` vertices: those listed (vertex indices), or the
// first `count` with listed == nullptr, starting at entry (or vertex)
// `first`. The dynamic step passes the last substep's reaction candidates:
// no other fat point can be inside.
uint32_t count_inside_of(const SkinModel& model, const muscle::MuscleState& muscles, fx::Unit tolerance,
                         const SkinState& s, const int64_t* listed, uint32_t count, uint32_t first = 0);

}  // namespace sinew::elastic_skin
