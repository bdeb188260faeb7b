// Run-time state of one SPH elastic joint, carved at init from caller memory
// (sph_state_bytes). After sph_init nothing allocates; a step's work is
// bounded by the model's counts (particles x max_neighbours x substeps).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "sim_core/fixed/mat34.hpp"
#include "sph_model.hpp"

namespace sinew::sph {

// A pair of particles within the kernel from at least one side, found once
// per substep by the half-stencil search (sph_grid.hpp); both particles' sums
// take their side's term from it. The two sides differ only where an axis of
// (x_a - x_b) / h rounds on an exact half: there d_ba = -d_ab + 1 LSB, and
// s_ba may differ from s_ab (and one side may fall outside the kernel).
struct SphPair {
  uint16_t a, b;  // particle indices
  uint8_t sides;  // bit 0: b is in a's neighbourhood (a takes a term), bit 1: a in b's
  uint8_t half;   // bit k: axis k rounded on an exact half
  uint16_t reserved;
  uint32_t s_ab;  // q^2 seen from a, Q2.30
  uint32_t s_ba;  // q^2 seen from b, Q2.30
  int32_t d[3];   // (x_a - x_b) / h seen from a, Q2.30
};

struct SphStats {
  uint64_t steps = 0;
  uint32_t neighbour_overflow = 0;   // neighbours dropped by max_neighbours, last step
  uint32_t max_neighbour_count = 0;  // largest list, last step
  uint64_t neighbour_pairs = 0;      // pairs evaluated, last step (all substeps)
  uint32_t saturated = 0;            // values clamped, last step
  uint32_t candidate_builds = 0;     // substeps of the last step that listed the candidate pairs afresh
};

// A pair of particles closer than the candidates' reach when the candidates
// were listed (sph_grid.hpp): the search on one thread tests only these
// until a particle has moved too far from where it was then.
struct SphCandidate {
  uint16_t a, b;  // particle indices
};

struct SphState {
  const SphModel* model = nullptr;

  // Outputs, one entry per particle (SoA). Positions in Len, model space.
  std::span<fx::Len> position[3];
  std::span<Dens> pressure;    // rho - rho0 (Q8.24, normalised density units; x k_p = pressure)
  std::span<uint8_t> yielded;  // 1 while the particle meets the Tresca condition, eq. (4)
  // Outputs per joint, as of the tick's last substep.
  fx::Angle bend = 0;              // flexion caused by the particles about the joint axis (signed view)
  bool joint_yielded = false;      // at least yield_count particles yield
  uint32_t yielded_particles = 0;  // particles that yield
  fx::Mat34 distal_flexed{};       // distal joint's model transform with the bend applied
  // Skin displacement of eq. (2) for model->skin_vertex[k], Len, model space.
  std::span<fx::Len> skin_offset[3];

  // Internal.
  std::span<fx::Len> velocity[3];  // Len per substep
  std::span<fx::Len> ideal[3];     // skinned rest positions in the commanded pose
  std::span<fx::Len> scratch[3];   // accelerations, then displacements for eq. (2)
  std::span<Dens> density;
  std::span<Dens> rest_density;           // rho_min of eq. (4): the unloaded, steady state
  std::span<fx::Unit> inv_density;        // 1 / rho, Q2.30 (rho >= 1)
  std::span<uint32_t> cell;               // linear cell index per particle
  std::span<uint32_t> cell_start;         // cells + 1
  std::span<uint16_t> sorted;             // particle indices by cell, then index
  std::span<fx::Len> sorted_position[3];  // position[sorted[k]]: the search reads contiguous ranges
  // This substep's pairs. After the search on one thread or the ordered
  // scan: [0, pair_count), both sides' terms scattered from each pair.
  // After the search over the workers (gathered): particle i's pairs as a
  // are pairs[run_first[i], + run_count[i]), its pairs as b are listed by
  // b_pair[b_offset[i], b_offset[i + 1]), so each particle gathers its own
  // terms (sph_grid.hpp).
  std::span<SphPair> pairs;  // n * (max_neighbours + 1) + 1 (the spare entries of the searches' stores)
  uint32_t pair_count = 0;   // every pair kept
  bool gathered = false;
  std::span<uint32_t> run_first;  // n
  std::span<uint16_t> run_count;  // n
  std::span<uint32_t> b_offset;   // n + 1
  std::span<uint32_t> b_pair;     // as pairs
  // The candidate pairs of the search on one thread (sph_grid.hpp): listed
  // from the positions candidate_origin (Len) about the grid centre
  // candidate_centre; valid while every particle stays within
  // candidate_slack of its origin, both measured from their centres.
  std::span<SphCandidate> candidates;      // n * max_neighbours
  std::span<fx::Len> candidate_origin[3];  // n
  // Particle i's candidates as a: candidates[candidate_first[i], candidate_end[i]).
  std::span<uint32_t> candidate_first, candidate_end;  // n
  uint32_t candidate_count = 0;
  bool candidates_valid = false;
  uint32_t candidate_pause = 0;  // substeps left without candidates, after a list outgrew its room
  fx::Vec3 candidate_centre{0, 0, 0};
  std::span<uint16_t> neighbour_count;  // per particle, this substep, before max_neighbours
  std::span<int64_t> density_sum;       // sum of poly6 over the neighbourhood, Q30, self included
  std::span<int64_t> pressure_sum[3];   // per-particle sums of the pair terms, Q24 (accelerations)
  std::span<int64_t> viscosity_sum[3];  // Len per substep
  // Colour field (surface tension, Mueller 2003 §4.4), per particle, Q30:
  // sum_j (1 - q^2)^2 d_ij / rho_j and sum_j (1 - q^2)(3 - 7 q^2) / rho_j.
  // Empty when params.tension_gain is 0 (the term is off).
  std::span<int64_t> colour_gradient_sum[3];
  std::span<int64_t> colour_laplacian_sum;
  std::span<uint16_t> skin_particle;  // vertex k: [k * kMaxVertexNeighbours, + skin_count[k])
  std::span<int32_t> skin_weight;     // poly6 at rest, Q2.30
  std::span<uint8_t> skin_count;
  uint32_t grid_dim = 0;
  int64_t inertia_q12 = 0;       // sum over distal particles of |r_perp|^2, rig units^2, Q12
  int64_t yield_torque_q12 = 0;  // while the joint yields: |torque| when it began (rig unit x N, Q12); else 0
  SphStats stats;
};

size_t sph_state_bytes(const SphModel& model);

// Validates the model, carves the arena (8-byte aligned, >= sph_state_bytes),
// places the particles at their rest positions and computes each one's rest
// density. rest_transforms: model-space joint transforms of the rig's rest
// pose (engine.model right after engine_init).
LayerStatus sph_init(const SphModel& model, std::span<const fx::Mat34> rest_transforms, void* arena, size_t arena_bytes,
                     SphState* out);

// Places every particle on its skinned rest position for the given pose, at
// rest, and clears the yield memory (density extremes, flags, joint yield).
LayerStatus sph_reset(SphState* state, std::span<const fx::Mat34> transforms);

}  // namespace sinew::sph
