// The runtime pipeline: one tick of a compiled rig with any subset of its
// physical layers. pipeline_step (or pipeline_step_locals, from sampled
// poses) is the only stage loop: the daemon, `sinew-log render`, sinew-run,
// the viewer's shadow pipeline, sinew-pose --spec, the benches and the
// determinism workloads call it and keep none of their own. The stage table
// (stage_table.hpp) names the stages and their options for everything that
// lists them.
//
// Stages run in the order of stage_list.hpp; docs/pipeline.md says what
// each adds. The first, skinning, poses the skeleton and skins the mesh;
// a stage may then bend joints and recompute the skin once with the bends
// (flexed, bent), which becomes the reference R; every later stage adds its
// displacement from R.
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
#include "sim_core/engine/engine.hpp"
#include "sim_core/fixed/status.hpp"
#include "sim_core/layer/workers.hpp"
#include "stage.hpp"

namespace sinew::pipeline {

// The stage's name in the stage table (its name in stage_list.hpp).
const char* stage_name(Stage s);

struct PipelineOptions {
  // The layers that run: a compiled layer can be switched off at run time
  // (a layer the rig lacks is off whatever this says; skinning always runs).
  StageSet stages = StageSet::all();
  // The loop's tick rate; 0: the rate the rig's rate-dependent sections
  // were compiled for. Stages convert their rate-dependent gains at init
  // (stage_<name>.hpp says how; 1 kHz when neither says).
  uint32_t tick_hz = 0;
  // Threads the stages' per-element loops may run over (caller-owned, must
  // outlive the pipeline); null: the calling thread alone. The output words
  // are the same for any number of workers (sim_core/layer/workers.hpp);
  // the stage table's `parallel` says which stages use them.
  const layer::Workers* workers = nullptr;
  // Each stage's own options (StageData<stage>::Options, stage_<name>.hpp),
  // one member per line of stage_list.hpp named as the stage
  // (options.<stage>.<option>). The stage table's kStageOptions names each
  // with its key and range.
#define SINEW_STAGE_OPTIONS(name, enumerator, sections, doc) \
  [[no_unique_address]] StageData<Stage::enumerator>::Options name;
  SINEW_STAGE_LIST(SINEW_STAGE_OPTIONS)
#undef SINEW_STAGE_OPTIONS
};

enum class PipelineError : uint8_t {
  kNone = 0,
  kArena,     // memory missing, misaligned or too small
  kBadModel,  // a layer refused its model at init (message names it)
  kBadInput,  // fewer inputs than the rig's plus its external inputs
  kLayer,     // a layer step failed (message names it); see pipeline_step
};

using PipelineStatus = fx::Status<PipelineError>;

struct Pipeline {
  const rig::Rig* rig = nullptr;
  const LayerSet* layers = nullptr;
  PipelineOptions options;
  StageSet on;            // the stages that run (pipeline_stage_on)
  engine::Engine engine;  // skeleton, palette and the output vertices (every stage's)
  // Each stage's state (StageData<stage>::Run, stage_<name>.hpp), one member
  // per line of stage_list.hpp named as the stage (p.<stage>).
#define SINEW_STAGE_RUN(name, enumerator, sections, doc) [[no_unique_address]] StageData<Stage::enumerator>::Run name;
  SINEW_STAGE_LIST(SINEW_STAGE_RUN)
#undef SINEW_STAGE_RUN
  std::span<int32_t> flexed;            // the rig's inputs with a stage's joint bends added
  std::span<skeleton::LocalPose> bent;  // locals with those bends applied (pose-driven steps)
  std::span<int32_t> measured;          // pose-driven steps: DOF values read from the pose, then the external inputs
  bool pose_driven = false;             // this tick came from pipeline_step_locals
  std::span<fx::Len> reference[3];      // R: the skin every layer's displacement is taken from
  std::span<fx::Len> scratch[3];        // a layer's full-skin output before it is added
  std::span<fx::Len> node_outputs[3];   // a layer's node positions, the largest asked for
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

// Which rig inputs a source measures: caller-owned, one byte per rig input
// (nonzero: measured), read by every later step until set again; empty
// (the default) measures none. Synergies never add to a measured DOF
// (skeleton::dofs_to_locals): a glove that measures a DIP gets that angle,
// not the angle plus 2/3 of the PIP. A span shorter than the rig's inputs
// marks the rest unmeasured.
void pipeline_set_measured_inputs(Pipeline* p, std::span<const uint8_t> measured);

// Per-input flags a step reports (StepReport::input_flags).
enum InputFlag : uint8_t {
  kInputClamped = 1u << 0,  // the joint that owns the input was clamped at a limit this tick
  kInputYielded = 1u << 1,  // a physical layer's joint driven by the input yielded (its material gave way)
};

// What a step may be asked to do beside stepping; every field optional.
// sim_core reads no clock of its own: the caller passes one.
struct StepProbe {
  uint64_t (*now_ns)(void* context) = nullptr;  // a monotonic clock, ns; null: stages are not timed
  // Called after each stage that ran, with the pipeline as that stage left
  // it (e.g. the viewer keeps the plain skinning).
  void (*after_stage)(void* context, Stage stage, const Pipeline& p) = nullptr;
  void* context = nullptr;
};

// What a step did. Every field is written by each step that is given one.
struct StepReport {
  uint64_t stage_ns[kStageCount] = {};  // time in each stage, by the probe's clock (0: did not run or untimed)
  StageSet ran;                         // the stages that ran this tick
  // Caller-owned, one byte per input (rig inputs then external inputs) or
  // empty: set to the InputFlag bits of each input after the step.
  std::span<uint8_t> input_flags;
};

// The whole tick: every stage that is on, in order. The error rule: the
// first stage that fails ends the tick there: the pose is what the stages
// before it made plus what the failing stage added for the instances that
// did step (a layer with several instances adds each one's displacement
// only after that instance's step succeeded), the later stages do not run, and the status names
// the failing stage. A skinning failure (inputs refused) leaves the previous
// pose.
// inputs: the rig's inputs, then its external inputs (input_count in all).
PipelineStatus pipeline_step(Pipeline* p, std::span<const int32_t> inputs, const StepProbe* probe = nullptr,
                             StepReport* report = nullptr);

// The whole tick from sampled local poses (one per joint, e.g. a glTF
// animation) instead of commanded DOFs. Layers that read DOF values get
// them measured from the pose: for each rotational DOF the twist
// of (rest rotation^-1 x local rotation) about its axis, for a translational
// one the offset from the rest translation along its axis; a stage's joint
// bends turn the driven joint's local rotation about the bend's axis. external: the rig's
// external inputs (may be shorter: missing ones read 0). The skinning stage
// is the posing from the locals; the error rule is pipeline_step's.
PipelineStatus pipeline_step_locals(Pipeline* p, std::span<const skeleton::LocalPose> locals,
                                    std::span<const int32_t> external, const StepProbe* probe = nullptr,
                                    StepReport* report = nullptr);

}  // namespace sinew::pipeline
