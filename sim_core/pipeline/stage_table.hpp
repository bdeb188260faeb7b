// The stage table, expanded from the pipeline's only list of its layers
// (stage_list.hpp). Each row holds
// the stage's functions (stage_fns.hpp, one shape for every layer):
// pipeline_state_bytes, pipeline_init and pipeline_step are loops over it.
// Everything that names layers or their run-time options (sinewd's [layers]
// keys, its start-up description and statistics, the recording header,
// sinew-run's layer list, the viewer) iterates these two tables, so adding a
// layer adds its stage files and a line to stage_list.hpp, and no line to the
// pipeline's loops, firmware or the tools' plumbing.
#pragma once

#include <cstddef>
#include <cstdint>

#include "pipeline.hpp"
#include "sim_core/rig/message.hpp"
#include "stage_fns.hpp"

namespace sinew::pipeline {

struct StageInfo {
  Stage stage;
  // The stage's name: its key in sinewd's [layers] (a flag), in a
  // recording's description and in the statistics.
  const char* name;
  // The rig spec's sections that compile the layer (rigc), for messages
  // about a layer the rig lacks.
  const char* rig_sections;
  const char* doc;  // the document that describes it
  // Loads the stage's layer sections of a blob (every section's structure
  // already checked against its descriptor, the external inputs already in
  // `set`) into `set`, running the layer's validator on each; sections of
  // other ids are skipped. Errors name the section, instance and field.
  rig::LoadStatus (*load)(std::span<const SectionView> sections, const rig::Rig& rig, LayerSet* set);
  // The instances of the layer the rig carries (0: the rig lacks it);
  // skinning: 1.
  uint32_t (*compiled)(const LayerSet& layers);
  // The shared buffers the stage needs when it is on.
  stages::SharedNeeds (*shares)(const rig::Rig& rig, const LayerSet& layers);
  // Appends the layer as a rig carries it, "<name>(<joint>)" once per
  // instance and space-separated; nothing when the rig lacks it.
  void (*describe)(const rig::Rig& rig, const LayerSet& layers, rig::MessageBuilder* out);
  // Every compiled instance's model against the rig, by the layer's own
  // validator (the loader ran it too; a LayerSet built by hand meets it at
  // pipeline_init). kBadModel naming the layer, the instance and the field.
  PipelineStatus (*validate)(const rig::Rig& rig, const LayerSet& layers);
  // Bytes of the stage's state in the pipeline's arena when it is on.
  size_t (*state_bytes)(const rig::Rig& rig, const LayerSet& layers, const PipelineOptions& options);
  // Sets the stage's state in the pipeline at the rest pose, carving its
  // block (8-byte aligned, state_bytes long). Runs in Stage order: a later
  // stage may read what an earlier one set (the skinning's rest pose).
  PipelineStatus (*init)(Pipeline* p, uint8_t* block, size_t bytes);
  // One tick of the stage (inputs: the rig's, then the external inputs);
  // adds the layer's displacement from the reference to the skin.
  PipelineStatus (*step)(Pipeline* p, std::span<const int32_t> inputs);
  // After a step: ORs the stage's InputFlag bits into flags (one byte per
  // input, rig inputs then external inputs; may be shorter than the inputs).
  void (*flag_inputs)(const Pipeline& p, std::span<uint8_t> flags);
  // Whether its step spreads its per-element loops over
  // PipelineOptions::workers (StageData::parallel, stage_<name>.hpp).
  bool parallel;
};

// In Stage order, one row per line of stage_list.hpp (a static_assert in
// stage_table.cpp checks the order).
#define SINEW_STAGE_ROW(name, enumerator, sections, doc) \
  {Stage::enumerator,                                    \
   #name,                                                \
   sections,                                             \
   doc,                                                  \
   stages::name##_load,                                  \
   stages::name##_compiled,                              \
   stages::name##_shares,                                \
   stages::name##_describe,                              \
   stages::name##_validate,                              \
   stages::name##_state_bytes,                           \
   stages::name##_init,                                  \
   stages::name##_step,                                  \
   stages::name##_flag_inputs,                           \
   StageData<Stage::enumerator>::parallel},
inline constexpr StageInfo kStages[kStageCount] = {SINEW_STAGE_LIST(SINEW_STAGE_ROW)};
#undef SINEW_STAGE_ROW

// Every stage's option rows (StageData<stage>::options, stage_<name>.hpp),
// in stage order.
#define SINEW_STAGE_OPTION_COUNT(name, enumerator, sections, doc) +StageData<Stage::enumerator>::options.size()
inline constexpr size_t kStageOptionCount = 0 SINEW_STAGE_LIST(SINEW_STAGE_OPTION_COUNT);
#undef SINEW_STAGE_OPTION_COUNT
inline constexpr std::array<StageOption, kStageOptionCount> kStageOptions = [] {
  std::array<StageOption, kStageOptionCount> all{};
  size_t k = 0;
#define SINEW_STAGE_OPTION_ROWS(name, enumerator, sections, doc) \
  for (const StageOption& o : StageData<Stage::enumerator>::options) all[k++] = o;
  SINEW_STAGE_LIST(SINEW_STAGE_OPTION_ROWS)
#undef SINEW_STAGE_OPTION_ROWS
  return all;
}();

// An option's value in a set of options (its flag, 0 or 1, or its number).
inline uint32_t option_value(const StageOption& option, PipelineOptions o) {
  return option.kind == OptionKind::kNumber ? *option.number(&o) : (*option.flag(&o) ? 1u : 0u);
}

// The table row of a stage name, or null.
const StageInfo* find_stage(const char* name, size_t name_length);

// The layers a rig carries, each stage's describe() in stage order, or
// "none"; truncated to the buffer.
void describe_layers(const rig::Rig& rig, const LayerSet& layers, char* out, size_t capacity);

}  // namespace sinew::pipeline
