// What the skinning stage keeps: nothing of its own. The engine it runs is
// the pipeline's (every stage reads its skeleton and writes its skin).
#pragma once

#include "stage.hpp"

namespace sinew::pipeline {

struct SkinningLayers {};
struct SkinningRun {};
struct SkinningOptions {};

template <>
struct StageData<Stage::kSkinning> {
  using Layers = SkinningLayers;
  using Run = SkinningRun;
  using Options = SkinningOptions;
  // The rig's core sections carry the skeleton and the skin.
  static constexpr std::array<const layer::SectionDescriptor*, 0> sections = {};
  static constexpr std::array<StageOption, 0> options = {};  // none
  static constexpr bool parallel = true;                     // the skin's vertex loop over the workers
};

}  // namespace sinew::pipeline
