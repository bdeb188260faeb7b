// The engine step: joint inputs -> skeleton -> skinning palette -> skinned
// vertices. All state lives in one arena sized from the rig at init
// (engine_arena_bytes); a step never allocates and its work is bounded by the
// rig's counts (validated against the format maxima).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "sim_core/layer/workers.hpp"
#include "sim_core/skeleton/pose.hpp"
#include "sim_core/skin/skinning.hpp"

namespace sinew::engine {

struct StepStats {
  uint64_t steps = 0;
  uint32_t clamped_dofs = 0;  // in the last step
  uint32_t saturated = 0;     // values clamped by skinning in the last step
};

struct Engine {
  const rig::Rig* rig = nullptr;
  std::span<skeleton::LocalPose> locals;
  std::span<uint8_t> joint_flags;  // skeleton::JointFlag per joint, last step
  std::span<fx::Mat34> model;      // model-space joint transforms
  std::span<fx::Mat34> palette;    // skinning matrices
  std::span<fx::DualQuat> dual;    // DQS palette (empty if the rig has no DQS vertex)
  skin::SkinnedVertices vertices;  // outputs, SoA
  // Caller-owned, empty or one byte per rig input: nonzero marks a DOF a
  // source measures, which synergies leave alone (skeleton::dofs_to_locals).
  std::span<const uint8_t> measured_inputs;
  StepStats stats;
};

size_t engine_arena_bytes(const rig::Rig& rig);

// Carves the arena (8-byte aligned, >= engine_arena_bytes) and sets the rest
// pose. Returns false if the arena is too small or misaligned.
bool engine_init(const rig::Rig& rig, void* arena, size_t arena_bytes, Engine* out);

// One step from commanded DOF inputs (see skeleton::dofs_to_locals for units).
// Returns false, changing nothing, if fewer than rig.input_count inputs are given.
// workers (optional): the vertex loop over these; every vertex is skinned
// alone, so the words and the saturation count are the same for any number
// of them (sim_core/layer/workers.hpp).
bool engine_step(Engine* e, std::span<const int32_t> inputs, const layer::Workers* workers = nullptr);

// One step from externally sampled local transforms (e.g. a glTF animation),
// one per joint. Returns false, changing nothing, on a size mismatch.
bool engine_step_locals(Engine* e, std::span<const skeleton::LocalPose> locals);

}  // namespace sinew::engine
