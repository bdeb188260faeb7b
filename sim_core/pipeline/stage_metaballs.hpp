// What the metaballs stage keeps (metaballs-pbd-skinning; docs/metaballs.md):
// at most one metaballs skin.
#pragma once

#include "sim_core/metaballs/metaballs_section.hpp"
#include "sim_core/metaballs/state.hpp"
#include "stage.hpp"

namespace sinew::pipeline {

struct MetaballsLayers {
  bool present = false;
  metaballs::MetaballModel model;
};

struct MetaballsRun {
  bool on = false;  // initialised: the stage runs
  metaballs::MetaballState state;
};

struct MetaballsOptions {};

template <>
struct StageData<Stage::kMetaballs> {
  using Layers = MetaballsLayers;
  using Run = MetaballsRun;
  using Options = MetaballsOptions;
  static constexpr std::array<const layer::SectionDescriptor*, 1> sections = {&metaballs::kMetaballsSection};
  static constexpr std::array<StageOption, 0> options = {};  // none
  static constexpr bool parallel = true;                     // per-vertex deformation over the workers
};

}  // namespace sinew::pipeline
