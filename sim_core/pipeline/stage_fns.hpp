// The functions of every stage, with one shape for all of them (the stage
// table, stage_table.hpp, documents each), so the pipeline's init and step
// are loops over the table and a new layer is its stage files
// (stage_<name>.hpp with its StageData, stage_<name>.cpp) plus one line in
// stage_list.hpp and one include in stage_data.hpp. Each
// stage file adapts its layer's own jobs (<layer>_validate, _state_bytes,
// _init, _step, all returning layer::LayerStatus) to the pipeline: which
// instances the rig carries, where their state lives in the pipeline's arena,
// and how their displacement is added to the skin.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "pipeline.hpp"
#include "section_view.hpp"
#include "sim_core/rig/message.hpp"

namespace sinew::pipeline {

namespace stages {

// The buffers a stage that is on needs from those the stages share (carved
// once, after the stages' own blocks, each the largest any stage asks for).
struct SharedNeeds {
  bool reference = false;         // R, the skin displacements are taken from (rig vertices)
  bool bent_pose = false;         // flexed inputs and bent locals (a stage bends joints)
  uint32_t scratch_vertices = 0;  // a layer's output before it is added, per axis
  uint32_t node_outputs = 0;      // a layer's node positions, per axis
};

#define SINEW_DECLARE_STAGE(name, enumerator, sections, doc)                                           \
  rig::LoadStatus name##_load(std::span<const SectionView> views, const rig::Rig& rig, LayerSet* set); \
  uint32_t name##_compiled(const LayerSet& layers);                                                    \
  SharedNeeds name##_shares(const rig::Rig& rig, const LayerSet& layers);                              \
  void name##_describe(const rig::Rig& rig, const LayerSet& layers, rig::MessageBuilder* out);         \
  PipelineStatus name##_validate(const rig::Rig& rig, const LayerSet& layers);                         \
  size_t name##_state_bytes(const rig::Rig& rig, const LayerSet& layers, const PipelineOptions& o);    \
  PipelineStatus name##_init(Pipeline* p, uint8_t* block, size_t bytes);                               \
  PipelineStatus name##_step(Pipeline* p, std::span<const int32_t> inputs);                            \
  void name##_flag_inputs(const Pipeline& p, std::span<uint8_t> flags);

SINEW_STAGE_LIST(SINEW_DECLARE_STAGE)
#undef SINEW_DECLARE_STAGE

// A failed stage's status: "<what>[index]: <detail>" (index when >= 0).
PipelineStatus stage_fail(PipelineError e, const char* what, const char* detail = nullptr, int64_t index = -1);

// out = out + (layer - reference), saturated: the superposition rule
// (docs/pipeline.md); counts the saturations in p->saturated.
void add_displacement(Pipeline* p, int axis, uint32_t v, fx::Len layer);
// The same for vertices 0 .. layer.size() - 1 of one axis, in one loop the
// compiler vectorises (a layer that covers every vertex).
void add_displacements(Pipeline* p, int axis, std::span<const fx::Len> layer);

// The skin as it is now becomes the reference R the layers displace from.
void take_reference(Pipeline* p);

}  // namespace stages
}  // namespace sinew::pipeline
