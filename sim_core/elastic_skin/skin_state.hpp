// Runtime state of the elastic skin, carved from caller memory at init.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "sim_core/muscle/layer_status.hpp"
#include "skin_model.hpp"

namespace sinew::elastic_skin {

using muscle::LayerError;
using muscle::LayerStatus;

struct SkinStats {
  uint64_t steps = 0;
  uint32_t iterations = 0;      // relaxations run in the last step
  fx::Len max_relax_first = 0;  // largest relaxation vector of the first iteration, last step
  fx::Len max_relax_last = 0;   // ... of the last iteration
  uint32_t collisions = 0;      // vertices pushed out of their collision sphere, last step (all iterations)
  uint32_t reactions = 0;       // vertices pushed out of a primitive, last step (all iterations)
  uint32_t inside_after = 0;    // fat points still inside an active primitive after the step (F < 1 - 2^-10)
  uint32_t saturated = 0;       // clamped accumulations, last step
  uint8_t converged = 0;        // static: stopped on solver.tolerance before the iteration count
  uint32_t substeps = 0;        // dynamic: substeps run in the last step
  fx::Len residual = 0;         // static: == max_relax_last; dynamic: largest move of the last substep
  uint32_t omega_max = 0;       // dynamic: the Gershgorin bound of the stiffest vertex's omega, rad/s (floor)
  uint32_t carried = 0;         // dynamic: vertices whose anchor's acceleration was capped this step
};

struct SkinState {
  uint32_t vertex_count = 0;
  std::span<fx::Len> position[3];       // relaxed skin, SoA (the layer's output)
  std::span<fx::Len> anchor[3];         // virtual anchors of this step, SoA
  std::span<fx::Len> previous[3];       // positions at the start of the current iteration
  std::span<fx::Unit> normal[3];        // anchor normals of this step, Q2.30, SoA
  std::span<fx::Len> sphere_centre[3];  // static mode: the collision spheres' centres of this step (relaxation.hpp)
  // Static mode along the anchor normal: each fat point's offset from its
  // vertex, fat * n (Len), for this step (reaction.hpp); valid while
  // fat_offsets is set.
  std::span<fx::Len> fat_offset[3];
  uint8_t fat_offsets = 0;
  std::span<int64_t> force[3];  // per-iteration accumulators: sum k (Q16.16) * force (Len)
  std::span<int64_t> weight;    // per-iteration accumulators: sum k
  // Largest relaxation vector per iteration of the last step (kMaxIterations
  // entries): the largest net move of a vertex in that round, relaxation and
  // constraints together, so it tends to zero at (constrained) equilibrium.
  std::span<fx::Len> max_relax;
  // Dynamic mode only (empty in static mode):
  std::span<int64_t> fine[3];  // positions, Q28.36 rig units (position = fine rounded to Q12.20)
  // Q44.20 rig units / s between steps; within a step the displacement per
  // substep, Q28.36 (skin_dynamic.cpp).
  std::span<int64_t> velocity[3];
  std::span<fx::Len> anchor_start[3];  // virtual anchors at the start of the step
  std::span<int64_t> anchor_step[3];   // (anchor - anchor_start) / n: the anchor's move per substep, Q28.36
  std::span<fx::Len> band_start[3];    // rubber-band targets at the start of the step, one per band
  std::span<fx::Len> band_end[3];      // ... at its end
  // solver.fat_normal = kSurface only (else empty): the skin mesh's vertex
  // normals of the last estimate, Q2.30 (zero: none, the anchor normal rules).
  std::span<fx::Unit> surface_normal[3];
  // Dynamic mode with SkinIntegrator::kRelaxation only (else empty),
  // surface_relaxation.hpp:
  std::span<int64_t> step_start[3];        // positions at the step's start, Q28.36
  std::span<int64_t> bend[3];              // u = L(x - a), the umbrella vectors, Q28.36
  std::span<int64_t> inverse_diagonal;     // 1 / D of each vertex's row, Q30
  std::span<int64_t> linear_gain;          // K of the row's terms linear in x_i alone (inertia, anchor, bands), Q30
  std::span<fx::Unit> reaction_normal[3];  // the step's reaction direction, Q2.30 (zero: no reaction)
  std::span<int64_t> reaction_floor;       // lowest n . x the reaction lets the vertex take, Q28.36
  // The edges at each vertex (CSR, filled at init from the model's edges,
  // in edge order): vertex v's are the edge indices
  // incident_edge[incident_offset[v] .. incident_offset[v + 1]).
  std::span<uint32_t> incident_offset;  // vertex_count + 1
  std::span<uint32_t> incident_edge;    // 2 edges
  std::span<uint8_t> incident_at_b;     // beside incident_edge: 1 where the vertex is the edge's b end
  std::span<int32_t> inverse_degree;    // relaxation integrator only: 1 / (edges at the vertex), Q2.30 (0 for none)
  // Relaxation integrator only, beside incident_edge: each slot's other end
  // j and its 1 / degree (inverse_degree[j]), so a sweep reads neither the
  // edge record nor the far vertex's row for them; and each edge's spring
  // gain h^2 k_e / m of the step (Q30).
  std::span<uint32_t> incident_neighbour;
  std::span<int32_t> neighbour_inverse_degree;
  std::span<int64_t> edge_gain;
  // The rubber bands at each vertex (CSR, in band order, filled at init):
  // vertex v's are band_at[band_offset[v] .. band_offset[v + 1]).
  std::span<uint32_t> band_offset;  // vertex_count + 1
  std::span<uint32_t> band_at;      // one per band
  // The relaxation round's per-edge pull (relaxation.cpp), computed once per
  // edge and gathered by both endpoints: k'_e (Q16.16, <= 2^24) and the
  // force on endpoint a (Len); zero for an edge that pulls with nothing.
  std::span<int32_t> edge_stiffness;
  std::span<fx::Len> edge_pull[3];
  // The static relaxation's vertices and edges (filled at init): the
  // region and its halo (SkinModel::region), ascending, and the edges with
  // an end among them, in edge order; every vertex and edge in dynamic mode
  // or without a region. moving_vertex[0 .. moving_vertices), moving_edge[0
  // .. moving_edges).
  std::span<uint32_t> moving_vertex;
  std::span<uint32_t> moving_edge;
  uint32_t moving_vertices = 0, moving_edges = 0;
  // The vertices whose anchors a static step maps (ascending): the moving
  // ones and the held ones the moving edges reach, whose anchors are their
  // positions. A held vertex beyond them is never read, and its state is
  // not kept. mapped_vertex[0 .. mapped_vertices).
  std::span<uint32_t> mapped_vertex;
  uint32_t mapped_vertices = 0;
  uint8_t started = 0;
  uint32_t step_rate = 0;  // dynamic: the substep rate (1/s) anchor_step is per
  SkinStats stats;
};

size_t skin_state_bytes(const SkinModel& model);

// Carves `memory` (8-byte aligned, >= skin_state_bytes). kArena on failure.
LayerStatus skin_init(const SkinModel& model, void* memory, size_t bytes, SkinState* out);

}  // namespace sinew::elastic_skin
