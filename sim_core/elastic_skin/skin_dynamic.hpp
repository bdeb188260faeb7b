// Dynamic elastic skin (LEMAN §3, §5.4-5.6, §6.11): the skin as a mass-spring
// surface with a velocity per vertex, advanced by the tick's time step in
// fixed substeps. The integrator, its stability bound and the units are in
// skin_model.hpp (SkinSolverParams).
//
// Fixed point, every product rounded half up and saturated:
//   positions  fine:  Q28.36 rig units (int64); output Q12.20, rounded
//   velocities       Q44.20 rig units / s (int64), clamped to +-2^46
//   accelerations    Q44.20 rig units / s^2 (int64), clamped to +-2^46
//   gains k / m      Q16.16 1/s^2 (spring), c / m Q16.16 1/s (dashpot), int64
// Per substep j = 1..n of a tick:
//   1. anchors and band targets at start + (end - start) * j / n
//   2. accelerations: edges (§5.2 push-back rule), anchor springs, rubber
//      bands (spring + dashpot, §5.5), anchor dashpots, gravity - a_base
//   3. v' then x' (skin_model.hpp); position = round(fine)
//   4. constraint_passes Gauss-Seidel passes of the sliding reactions with
//      the fat layer (global + per-point thickness along the anchor normal,
//      or with fat_normal = kSurface along the skin mesh's normal estimated
//      once per substep after step 3, surface_normals.hpp)
// Worst-case work per tick: n * (edges + bands + vertices * (1 +
// constraint_passes * primitives * newton_steps)); no allocation.
#pragma once

#include <span>

#include "sim_core/fixed/mat34.hpp"
#include "sim_core/muscle/muscle_model.hpp"
#include "sim_core/muscle/muscle_state.hpp"
#include "skin_state.hpp"

namespace sinew::elastic_skin {

// What a step needs besides the pose: the time base and the frame's motion.
struct SkinTick {
  uint32_t tick_hz = 0;  // steps per second, 1..kMaxTickHz (dynamic mode only)
  // Acceleration of the frame the bones are given in (e.g. a robot's base on
  // a moving vehicle), rig units / s^2, Q24.8: the skin feels -a_base.
  fx::Vec3 base_acceleration{0, 0, 0};
};

// Substeps of one tick: ceil(substep_hz / tick_hz), at least 1; 0 if above
// max_substeps or tick_hz is 0.
uint32_t skin_substeps(const SkinSolverParams& p, uint32_t tick_hz);

// The dynamic step on validated inputs (skin_step checks them and calls it).
LayerStatus skin_dynamic_step(const SkinModel& model, const muscle::MuscleModel& muscles,
                              const muscle::MuscleState& mstate, std::span<const fx::Mat34> bones, const SkinTick& tick,
                              SkinState* state);

}  // namespace sinew::elastic_skin
