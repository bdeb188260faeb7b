// The pipeline's stages and a set of them, from the one list of them
// (stage_list.hpp); the stage table (stage_table.hpp) describes each.
#pragma once

#include <array>
#include <cstdint>

#include "sim_core/layer/section_format.hpp"
#include "stage_list.hpp"

namespace sinew::pipeline {

// In the order a tick runs them (stage_list.hpp).
#define SINEW_STAGE_ENUMERATOR(name, enumerator, sections, doc) enumerator,
enum class Stage : uint8_t { SINEW_STAGE_LIST(SINEW_STAGE_ENUMERATOR) };
#undef SINEW_STAGE_ENUMERATOR
#define SINEW_STAGE_ONE(name, enumerator, sections, doc) +1
inline constexpr uint32_t kStageCount = 0 SINEW_STAGE_LIST(SINEW_STAGE_ONE);
#undef SINEW_STAGE_ONE

// A set of stages, one bit per Stage. Skinning always runs: its bit is
// ignored where a set switches layers on or off.
struct StageSet {
  uint32_t bits = 0;

  static constexpr StageSet all() { return {(1u << kStageCount) - 1}; }
  static constexpr StageSet none() { return {}; }
  constexpr bool has(Stage s) const { return (bits >> static_cast<uint32_t>(s) & 1u) != 0; }
  constexpr void set(Stage s, bool on) {
    const uint32_t bit = 1u << static_cast<uint32_t>(s);
    bits = on ? (bits | bit) : (bits & ~bit);
  }
  constexpr bool operator==(const StageSet&) const = default;
};

// What a stage keeps, declared beside its stage file (stage_<name>.hpp):
//   Layers: its loaded models in the LayerSet (the blob's sections);
//   Run:    its state in the Pipeline (in the pipeline's arena);
//   Options: its run-time options in PipelineOptions;
//   sections: the rig sections it loads (a std::array of descriptors,
//             layer_sections.hpp lists them all).
// LayerSet, Pipeline and PipelineOptions hold one member of each per stage,
// named as the stage, expanded from stage_list.hpp: they name no layer
// themselves.
template <Stage S>
struct StageData;

}  // namespace sinew::pipeline
