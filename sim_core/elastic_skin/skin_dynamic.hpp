// Dynamic elastic skin (LEMAN §3, §5.4-5.6, §6.11): the skin as a mass-spring
// surface with a velocity per vertex, advanced by the tick's time step in
// fixed substeps. The integrator, its stability bound and the units are in
// skin_model.hpp (SkinSolverParams).
//
// Fixed point, every product rounded half up and saturated:
//   positions  fine:  Q28.36 rig units (int64); output Q12.20, rounded
//   velocities       Q44.20 rig units / s (int64) between steps, clamped to
//                    +-2^46; within a step the displacement per substep
//                    d = v h, Q28.36, clamped to +-2^50
//   gains            per substep: h^2 k / m and h c / m, Q30 (dimensionless;
//                    h^2 k / m <= 1 on a step the stability check admits),
//                    h^2 stiffness_scale / m Q46 per unit model stiffness
//   field            h^2 (gravity - a_base), Q28.36
// so a substep has products only: d' = (d + h^2 a + sum (h c_i / m) d_i) /
// (1 + h D) with 1 / (1 + h D) a Q30 factor fixed for the tick, x' = x + d'.
// Per substep j = 1..n of a tick:
//   1. anchors and band targets at start + j (end - start) / n
//   2. h^2 x accelerations: edges (§5.2 push-back rule), anchor springs, rubber
//      bands (spring + dashpot, §5.5), anchor dashpots, gravity - a_base
//   3. d' then x' (skin_model.hpp); position = round(fine)
//   4. the vertices within reach of an active primitive are listed, then
//      constraint_passes Gauss-Seidel passes of the sliding reactions with
//      the fat layer (global + per-point thickness along the anchor normal,
//      or with fat_normal = kSurface along the skin mesh's normal estimated
//      once per substep after step 3, surface_normals.hpp)
// Worst-case work per tick: n * (edges + bands + vertices * (1 +
// constraint_passes * primitives * newton_steps)); the first step adds 30
// rounds of the static relaxation, which start the skin at its equilibrium
// over the muscles rather than on its bare anchors; no allocation.
#pragma once

#include <span>

#include "sim_core/fixed/mat34.hpp"
#include "sim_core/layer/workers.hpp"
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
  // The largest acceleration of a virtual anchor the skin feels, rig units /
  // s^2, Q24.8 (0: no limit). A bone that jumps within a tick (a glitching
  // sensor, a joint driven from one limit to the other) would hit the skin
  // with its anchor dashpots' whole impulse and fling it off the limb; the
  // part of an anchor's velocity change beyond this limit carries the
  // vertex with it instead (it moves as if rigidly attached), so only a
  // physically plausible acceleration excites the skin's dynamics.
  int32_t max_anchor_acceleration = 0;
  // Threads the static step spreads its per-vertex and per-edge loops over
  // (null: the calling thread). The words written are the same for any
  // number of them (sim_core/layer/workers.hpp).
  const layer::Workers* workers = nullptr;
};

// Substeps of one tick: ceil(substep_hz / tick_hz), at least 1; 0 if above
// max_substeps or tick_hz is 0.
uint32_t skin_substeps(const SkinSolverParams& p, uint32_t tick_hz);

// The dynamic step on validated inputs (skin_step checks them and calls it).
LayerStatus skin_dynamic_step(const SkinModel& model, const muscle::MuscleModel& muscles,
                              const muscle::MuscleState& mstate, std::span<const fx::Mat34> bones, const SkinTick& tick,
                              SkinState* state);

}  // namespace sinew::elastic_skin
