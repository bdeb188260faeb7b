// What the anatomy stage keeps (anatomically-based-modeling,
// leman-elastic-skin; docs/anatomy.md): the muscles and, over them, the
// optional elastic skin.
#pragma once

#include <cstdint>
#include <span>

#include "layer_format.hpp"
#include "sim_core/elastic_skin/skin_section.hpp"
#include "sim_core/elastic_skin/skin_state.hpp"
#include "sim_core/fixed/q_formats.hpp"
#include "sim_core/muscle/muscle_section.hpp"
#include "sim_core/muscle/muscle_state.hpp"
#include "stage.hpp"

namespace sinew::pipeline {

struct AnatomyLayers {
  bool has_muscles = false;
  muscle::MuscleModel muscles;
  bool has_skin = false;  // needs the muscles
  elastic_skin::SkinModel skin;
  std::span<const uint32_t> skin_region;         // vertices the skin displaces (empty: all)
  std::span<const fx::Unit> skin_region_weight;  // their weights, Q2.30 in (0, 1]
  // The external inputs of the base's acceleration, x, y, z (SKIN version 5),
  // or kNoExternalInput: the dynamic skin then feels no base motion.
  uint32_t skin_base_acceleration[3] = {kNoExternalInput, kNoExternalInput, kNoExternalInput};
};

struct AnatomyRun {
  bool on = false;  // initialised: the stage runs
  muscle::MuscleState muscles;
  elastic_skin::SkinState skin;
};

// Its run-time options ([layers] skin_iterations,
// skin_max_anchor_acceleration; the stage table's option rows).
struct AnatomyOptions {
  uint32_t skin_iterations = 0;  // elastic-skin relaxations per tick, 0..256; 0 keeps the rig's
  // The dynamic skin's limit on the acceleration of its anchors, m/s^2
  // (elastic_skin::SkinTick::max_anchor_acceleration; 0: none, 1..32767).
  // 500 m/s^2 (about 50 g) is above a boxer's fist; a bone that moves
  // faster than that within a tick is taken as a jump, and the skin is
  // carried with it instead of being flung off the limb.
  uint32_t skin_max_anchor_acceleration = 500;
  // The static skin relaxes every vertex, not only its support region and
  // the halo about it (elastic_skin::SkinModel::region): the whole-mesh
  // simulation, whose far vertices the stage does not read.
  bool skin_whole_mesh = false;
};

// Its options' fields in PipelineOptions (stage_anatomy.cpp).
uint32_t* anatomy_skin_iterations_option(PipelineOptions* o);
uint32_t* anatomy_skin_max_anchor_acceleration_option(PipelineOptions* o);
bool* anatomy_skin_whole_mesh_option(PipelineOptions* o);

template <>
struct StageData<Stage::kAnatomy> {
  using Layers = AnatomyLayers;
  using Run = AnatomyRun;
  using Options = AnatomyOptions;
  static constexpr std::array<StageOption, 3> options = {
      StageOption{"skin_iterations",
                  Stage::kAnatomy,
                  OptionKind::kNumber,
                  nullptr,
                  {nullptr, nullptr},
                  anatomy_skin_iterations_option,
                  0,
                  elastic_skin::kMaxIterations,
                  "skin_iterations",
                  true,
                  "elastic-skin relaxations per tick; 0 keeps the rig's (docs/anatomy.md)"},
      StageOption{"skin_max_anchor_acceleration",
                  Stage::kAnatomy,
                  OptionKind::kNumber,
                  nullptr,
                  {nullptr, nullptr},
                  anatomy_skin_max_anchor_acceleration_option,
                  0,
                  32767,
                  "skin_max_anchor_acceleration",
                  false,
                  "the dynamic skin's cap on its anchors' acceleration, m/s^2; 0: none (docs/anatomy.md)"},
      StageOption{"skin_whole_mesh",
                  Stage::kAnatomy,
                  OptionKind::kFlag,
                  anatomy_skin_whole_mesh_option,
                  {nullptr, nullptr},
                  nullptr,
                  0,
                  0,
                  "skin_whole_mesh",
                  false,
                  "the static elastic skin relaxes every vertex, not only its support region and halo "
                  "(docs/anatomy.md)"},
  };
  // The skin needs the muscles (its descriptor says so).
  static constexpr std::array<const layer::SectionDescriptor*, 2> sections = {&muscle::kMusclesSection,
                                                                              &elastic_skin::kSkinSection};
  static constexpr bool parallel = true;  // the static skin step's per-vertex and per-edge loops over the workers
};

}  // namespace sinew::pipeline
