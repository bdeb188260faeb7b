// Internal stages of metaballs::step (one file each); sizes already checked.
#pragma once

#include <span>

#include "sim_core/skin/skinning.hpp"
#include "state.hpp"

namespace sinew::metaballs::detail {

// balls.cpp: stages 1 and 2.
void compute_bones(const MetaballModel& m, std::span<const fx::Mat34> joint_model, MetaballState* s);
void compute_balls(const MetaballModel& m, MetaballState* s);

// pbd.cpp: stage 3.
void solve_pbd(const MetaballModel& m, MetaballState* s);

// deform.cpp: stage 4.
void deform_vertices(const MetaballModel& m, std::span<const fx::Mat34> joint_model, MetaballState* s,
                     const skin::SkinnedVertices& out);

// smoothing.cpp: stage 5.
void smooth_joint_region(const MetaballModel& m, MetaballState* s, const skin::SkinnedVertices& out);

// overlap.cpp: stage 6. Returns the number of projected vertices.
uint32_t resolve_overlaps(const MetaballModel& m, std::span<const fx::Mat34> joint_model, const MetaballState& s,
                          const skin::SkinnedVertices& out);

}  // namespace sinew::metaballs::detail
