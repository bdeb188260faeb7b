// The SPH elastic-joint step as first written (per-particle neighbour lists,
// every pair evaluated from both sides), kept verbatim as the reference the
// optimised sim_core/sph must match word for word: the equivalence test runs
// both on the same inputs and compares every persistent state word, and the
// sph bench times it as its baseline. Its own copies of the kernels, grid and
// pose helpers, so later changes to sim_core/sph cannot leak into it. Host
// memory (std::vector): a test and bench helper, not a run-time module.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "sim_core/sph/sph_step.hpp"

namespace sinew::sph_reference_v1 {

struct Neighbour {
  uint16_t j;
  uint16_t reserved;
  uint32_t s;  // q^2, Q2.30
};

// The state fields of the first sph::SphState, each in its own vector.
struct RefState {
  const sph::SphModel* model = nullptr;
  std::vector<fx::Len> position[3];
  std::vector<sph::Dens> pressure;
  std::vector<uint8_t> yielded;
  fx::Angle bend = 0;
  bool joint_yielded = false;
  uint32_t yielded_particles = 0;
  fx::Mat34 distal_flexed{};
  std::vector<fx::Len> skin_offset[3];
  std::vector<fx::Len> velocity[3];
  std::vector<fx::Len> ideal[3];
  std::vector<fx::Len> scratch[3];
  std::vector<sph::Dens> density;
  std::vector<sph::Dens> rest_density;
  std::vector<fx::Unit> inv_density;
  std::vector<uint32_t> cell;
  std::vector<uint32_t> cell_start;
  std::vector<uint16_t> sorted;
  std::vector<Neighbour> neighbours;
  std::vector<uint8_t> neighbour_count;
  std::vector<uint16_t> skin_particle;
  std::vector<int32_t> skin_weight;
  std::vector<uint8_t> skin_count;
  uint32_t grid_dim = 0;
  int64_t inertia_q12 = 0;
  int64_t yield_torque_q12 = 0;
  sph::SphStats stats;
};

sph::LayerStatus ref_init(const sph::SphModel& model, std::span<const fx::Mat34> rest_transforms, RefState* out);
sph::LayerStatus ref_reset(RefState* state, std::span<const fx::Mat34> transforms);
sph::LayerStatus ref_step(RefState* state, const sph::SphInputs& inputs);
void ref_apply_skin(const RefState& state, std::span<fx::Len> position[3]);

}  // namespace sinew::sph_reference_v1
