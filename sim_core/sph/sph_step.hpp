// The SPH elastic-joint step (sph-elastic-joints-tresca §4), one tick:
//   inputs : model-space joint transforms of the commanded pose (the
//            engine's Engine::model after engine_step), an external force on
//            the distal bone, the Tresca switch;
//   outputs: (in SphState) particle positions / pressures / yield flags, the
//            bend of the joint, its yield flag, the flexed distal transform
//            and the skin displacement of eq. (2) for the vertices near the
//            joint.
// Call sequence with the engine: docs/sph.md.
#pragma once

#include <span>

#include "sim_core/layer/workers.hpp"
#include "sph_state.hpp"

namespace sinew::sph {

struct SphInputs {
  std::span<const fx::Mat34> transforms;  // one per rig joint, model space
  fx::Vec3 force{0, 0, 0};                // newtons, Q16.16, model space, acting at joint.load_point; |c| <= 2^30
  bool tresca = true;                     // apply the yield condition of eqs. (3)-(4)
  // The driven joint's angle in `transforms` is measured (a wearable's
  // sensor), hence already the truth under the external force: the force
  // does not turn the distal bone again, the bend stays 0 and the particles
  // only move the soft tissue (eq. (2) skin offsets). docs/sph.md, "Measured
  // and simulated joints".
  bool joint_measured = false;
  // Threads the step may spread its per-particle loops and its neighbour
  // search over (null: the calling thread); the same words for any number.
  const layer::Workers* workers = nullptr;
};

// Returns kBadInput, changing nothing, if a transform is missing or the
// force is out of range.
LayerStatus sph_step(SphState* state, const SphInputs& inputs);

// The external force of SphInputs for a force sensor that measures one
// scalar: `newtons` (Q16.16, clamped to +-16384 N, as is each component of
// the result: sph_step accepts it) acting at the load point along n x r,
// perpendicular to the flexion axis n and to the lever arm r from the joint
// to the load point, in the pose `transforms`. A positive
// force flexes the joint (positive bend about n), and every newton of it
// turns into torque. Zero if the lever arm is parallel to the axis; false
// only if the transforms span is too short.
bool sph_flexion_force(const SphModel& model, std::span<const fx::Mat34> transforms, int32_t newtons, fx::Vec3* out);

// Adds skin_offset to the engine's skinned positions of the near-joint
// vertices (position[c] indexed by rig vertex).
void sph_apply_skin(const SphState& state, std::span<fx::Len> position[3]);

}  // namespace sinew::sph
