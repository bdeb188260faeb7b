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
//             layer_sections.hpp lists them all);
//   options: its run-time options' rows (a std::array of StageOption, below;
//            the stage table's kStageOptions lists them all).
// LayerSet, Pipeline and PipelineOptions hold one member of each per stage,
// named as the stage, expanded from stage_list.hpp: they name no layer
// themselves.
template <Stage S>
struct StageData;

struct PipelineOptions;

// A run-time option of one layer: its key in sinewd's [layers], its field
// in its stage's PipelineOptions member, its range, and how a recording's
// description spells it.
enum class OptionKind : uint8_t {
  kFlag,    // true / false
  kChoice,  // one of two names, for false and for true
  kNumber,  // an unsigned integer in [min, max]
};

struct StageOption {
  const char* key = nullptr;  // in [layers]
  Stage stage{};              // the layer it tunes
  OptionKind kind{};
  bool* (*flag)(PipelineOptions* o) = nullptr;        // kFlag, kChoice: its field in o
  const char* choice[2] = {nullptr, nullptr};         // kChoice: the names of false and of true
  uint32_t* (*number)(PipelineOptions* o) = nullptr;  // kNumber: its field in o
  uint32_t min = 0, max = 0;                          // kNumber
  // Its key in a recording's description, a flag or a number.
  const char* recording_key = nullptr;
  // Written into every recording (a reader requires it), or only when it
  // differs from the default (options added after the format was fixed, so
  // that the recordings made before read as they did).
  bool recorded_always = false;
  const char* meaning = nullptr;  // one line, for messages and help
};

}  // namespace sinew::pipeline
