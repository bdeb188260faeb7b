// The skinning stage: commanded inputs -> skeleton -> skinned vertices (the
// engine; docs/numerics.md). Always on; its skin is the first reference.
#include "sim_core/engine/engine.hpp"
#include "stage_fns.hpp"

namespace sinew::pipeline::stages {

// The rig's core sections carry the skeleton and the skin (rig_init).
rig::LoadStatus skinning_load(std::span<const SectionView>, const rig::Rig&, LayerSet*) { return {}; }

uint32_t skinning_compiled(const LayerSet&) { return 1; }

// Plain skinning writes the output skin directly.
SharedNeeds skinning_shares(const rig::Rig&, const LayerSet&) { return {}; }

void skinning_describe(const rig::Rig&, const LayerSet&, rig::MessageBuilder*) {}

// rig_init validated the skeleton and the skin.
PipelineStatus skinning_validate(const rig::Rig&, const LayerSet&) { return {}; }

size_t skinning_state_bytes(const rig::Rig& rig, const LayerSet&, const PipelineOptions&) {
  return engine::engine_arena_bytes(rig);
}

PipelineStatus skinning_init(Pipeline* p, uint8_t* block, size_t bytes) {
  if (!engine::engine_init(*p->rig, block, bytes, &p->engine))
    return stage_fail(PipelineError::kArena, "skinning", "engine arena");
  return {};
}

PipelineStatus skinning_step(Pipeline* p, std::span<const int32_t> inputs) {
  if (!engine::engine_step(&p->engine, inputs.first(p->rig->input_count), p->options.workers))
    return stage_fail(PipelineError::kBadInput, "skinning", "engine step refused its inputs");
  take_reference(p);
  return {};
}

// The engine's clamp flags per joint, on each of the joint's inputs.
void skinning_flag_inputs(const Pipeline& p, std::span<uint8_t> flags) {
  const rig::Rig& rig = *p.rig;
  for (uint32_t j = 0; j < rig.joint_count(); ++j) {
    if ((p.engine.joint_flags[j] & skeleton::kJointClamped) == 0) continue;
    const rig::JointRecord& r = rig.joints[j];
    for (uint32_t d = 0; d < r.dof_count; ++d)
      if (r.first_input + d < flags.size()) flags[r.first_input + d] |= kInputClamped;
  }
}

}  // namespace sinew::pipeline::stages
