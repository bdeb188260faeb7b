// The runtime pipeline: one tick of a compiled rig with any subset of its
// physical layers. Every consumer (the daemon, sinew-run, sinew-pose --spec,
// the benches, the determinism workloads) drives this same code.
//
// Stages, in this order (docs/pipeline.md):
//   1. kSkinning   commanded inputs -> skeleton -> skinned vertices (engine).
//   2. kSph        every SPH joint steps on the commanded pose; their bends
//                  are added to the driven joints' first DOF (saturated),
//                  the skeleton and skin are recomputed once with them, and
//                  this skin becomes the reference R; then each joint adds its
//                  eq. (2) offsets of sph-elastic-joints-tresca.
//   3. kMetaballs  adds (metaballs skin - R) over every vertex.
//   4. kBarnet     each bar-net adds (wrapped skin - R) over its wrap vertices.
//   5. kAnatomy    muscles, then the elastic skin; adds (relaxed skin - R).
// The layers compose by superposition of their displacements from the same
// reference, so a vertex outside every layer's support keeps the skinned
// position bit for bit, and enabling one layer never rewrites another's work.
// Normals are the skinning's. Additions saturate to the Len range.
//
// Memory: one arena sized by pipeline_state_bytes(); a step never allocates
// and its work is bounded by the validated model counts.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "layer_set.hpp"
#include "sim_core/barnet/barnet_state.hpp"
#include "sim_core/elastic_skin/skin_state.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/fixed/status.hpp"
#include "sim_core/metaballs/state.hpp"
#include "sim_core/muscle/muscle_state.hpp"
#include "sim_core/sph/sph_state.hpp"

namespace sinew::pipeline {

enum class Stage : uint8_t { kSkinning = 0, kSph, kMetaballs, kBarnet, kAnatomy };
inline constexpr uint32_t kStageCount = 5;
const char* stage_name(Stage s);

struct PipelineOptions {
  // Switch compiled layers off at run time (a layer the rig lacks is off).
  bool sph = true, metaballs = true, barnet = true, anatomy = true;
  bool tresca = true;  // the SPH yield condition, eqs. (3)-(4)
  // The SPH joints' angles are measured (a wearable's sensors), hence already
  // the truth under the load: the particles move the soft tissue only and do
  // not bend the joint again (sph::SphInputs::joint_measured; docs/sph.md,
  // "Measured and simulated joints"). false: the joints are simulated.
  bool sph_joint_measured = false;
  uint32_t skin_iterations = 0;  // elastic-skin relaxations per tick; 0 keeps the rig's
  // The loop's tick rate; 0: the rate the rig's SPH joints were compiled
  // for. Another rate converts their gains at init (sph_gains_for_rate).
  // The dynamic elastic skin takes its time step from it too (0 and no SPH
  // rate: 1 kHz).
  uint32_t tick_hz = 0;
  // The dynamic skin's limit on the acceleration of its anchors, m/s^2
  // (elastic_skin::SkinTick::max_anchor_acceleration; 0: none, 1..32767).
  // 500 m/s^2 (about 50 g) is above a boxer's fist; a bone that moves
  // faster than that within a tick is taken as a jump, and the skin is
  // carried with it instead of being flung off the limb.
  uint32_t skin_max_anchor_acceleration = 500;
};

enum class PipelineError : uint8_t {
  kNone = 0,
  kArena,     // memory missing, misaligned or too small
  kBadModel,  // a layer refused its model at init (message names it)
  kBadInput,  // fewer inputs than the rig's plus its external inputs
  kLayer,     // a layer step failed (message names it); the skinned pose is kept
};

using PipelineStatus = fx::Status<PipelineError>;

// The SPH gains of a joint compiled for compiled_hz, converted for tick_hz:
// substeps max(2, ceil(200 / tick_hz)) (dt <= 5 ms, as rigc picks them);
// with rho = dt_new / dt_compiled = (compiled_hz x s_compiled) /
// (tick_hz x s_new) as the exact fraction N / D, the gains scale as their
// definitions in docs/sph.md do: k_e dt^2, k_p dt^2 / h, the surface
// tension 6 sigma h dt^2 / (m C) and the load gain by rho^2 (two roundings
// of x N / D, half up; the load gain saturates at its Q2.30 limit, as
// rigc's builder saturates it), mu dt by rho, and the kept
// velocity 1 - c dt as 1 - (1 - damping) rho. The particles, h and the
// Tresca limit do not depend on the rate. Fails (kBadModel, naming the
// gain) when the rate needs more than 16 substeps or a gain leaves its range;
// for any u32 rates, a scaled gain beyond int64 saturates (then is refused,
// or for the load gain saturates at its Q2.30 limit) rather than overflowing.
PipelineStatus sph_gains_for_rate(const sph::SphParams& compiled, uint32_t compiled_hz, uint32_t tick_hz,
                                  sph::SphParams* out);

struct Pipeline {
  const rig::Rig* rig = nullptr;
  const LayerSet* layers = nullptr;
  PipelineOptions options;
  engine::Engine engine;                   // skeleton, palette and the output vertices
  sph::SphModel sph_model[kMaxSphJoints];  // the layers' SPH models, gains for the loop's rate
  sph::SphState sph[kMaxSphJoints];
  uint32_t sph_count = 0;  // SPH joints running (0 when switched off)
  bool sph_started = false;
  metaballs::MetaballState metaballs;
  muscle::MuscleState muscles;
  elastic_skin::SkinState skin;
  barnet::BarnetState barnet[kMaxBarnets];
  uint32_t barnet_count = 0;
  bool metaballs_on = false, anatomy_on = false;
  std::span<int32_t> flexed;            // the rig's inputs with the SPH bends added
  std::span<skeleton::LocalPose> bent;  // locals with the SPH bends applied (pose-driven steps)
  std::span<int32_t> measured;          // pose-driven steps: DOF values read from the pose, then the external inputs
  bool pose_driven = false;             // this tick came from pipeline_step_locals
  std::span<fx::Len> reference[3];      // R: the skin every layer's displacement is taken from
  std::span<fx::Len> scratch[3];        // a layer's full-skin output before it is added
  std::span<fx::Len> barnet_nodes[3];   // bar-net node outputs, the largest net's size
  uint32_t input_count = 0;             // rig inputs + external inputs
  uint32_t saturated = 0;               // displacement sums clamped, last step
};

size_t pipeline_state_bytes(const rig::Rig& rig, const LayerSet& layers, const PipelineOptions& options);

// Carves the arena (8-byte aligned, >= pipeline_state_bytes) and sets every
// layer at the rig's rest pose. rig and layers must outlive the pipeline,
// and the pipeline must stay where it was initialised (its layer states
// point at its own models).
PipelineStatus pipeline_init(const rig::Rig& rig, const LayerSet& layers, const PipelineOptions& options, void* arena,
                             size_t arena_bytes, Pipeline* out);

// Whether a stage does anything for this rig and these options.
bool pipeline_stage_on(const Pipeline& p, Stage s);

// One stage; stages must run in order, kSkinning first, each once per tick.
// inputs: the rig's inputs, then its external inputs (input_count in all).
PipelineStatus pipeline_run_stage(Pipeline* p, Stage s, std::span<const int32_t> inputs);

// The whole tick: every stage that is on, in order. On a layer error the
// later stages still run; the first error is returned.
PipelineStatus pipeline_step(Pipeline* p, std::span<const int32_t> inputs);

// The whole tick from sampled local poses (one per joint, e.g. a glTF
// animation) instead of commanded DOFs. Layers that read DOF values (bar-net
// loads) get them measured from the pose: for each rotational DOF the twist
// of (rest rotation^-1 x local rotation) about its axis, for a translational
// one the offset from the rest translation along its axis; SPH bends turn
// the driven joint's local rotation about the SPH axis. external: the rig's
// external inputs (may be shorter: missing ones read 0).
PipelineStatus pipeline_step_locals(Pipeline* p, std::span<const skeleton::LocalPose> locals,
                                    std::span<const int32_t> external);

// True when an SPH joint driven by rig input `input` has yielded.
bool pipeline_input_yielded(const Pipeline& p, uint32_t input);

}  // namespace sinew::pipeline
