// The skin mesh's vertex normals, re-estimated from the deformed skin
// (LEMAN §5.6: the fat layer lies along the skin's current normal):
//   n(v) = unit( sum over faces f around v of (p_b - p_a) x (p_c - p_a) )
// i.e. the faces' normals weighted by twice their areas, turned to the side
// of the vertex's anchor normal (outward whatever the faces' winding).
//
// Fixed point: edge vectors are the Len differences shifted right by 2
// (|e| <= 2^30, each product <= 2^60, each face's cross < 2^61), summed per
// vertex in int64 with saturation (reached only by faces over 2^29 Len,
// 512 rig units, across), narrowed to 30 bits and normalised division-free
// (fx::normalize_fast). A vertex with no face, or whose faces cancel, gets
// the zero vector (callers fall back to the anchor normal).
// Work: O(triangles + vertices); no allocation (SkinState::force is the
// accumulator, free between the relaxation's or the integrator's uses).
#pragma once

#include "skin_state.hpp"

namespace sinew::elastic_skin {

// Writes s->surface_normal from s->position; needs solver.fat_normal ==
// kSurface (the spans are empty otherwise: then it does nothing). The
// triangles are validated (skin_check_indices).
// True when the fat lies along the skin mesh's normal (solver.fat_normal =
// kSurface, its normals carved): fat_direction then changes with the skin.
bool surface_mode(const SkinModel& model, const SkinState& s);

void estimate_surface_normals(const SkinModel& model, SkinState* s);

// The direction of vertex v's fat layer: its surface normal under
// kSurface where one exists, else its anchor normal (Q2.30).
fx::Vec3 fat_direction(const SkinModel& model, const SkinState& s, uint32_t v);

}  // namespace sinew::elastic_skin
