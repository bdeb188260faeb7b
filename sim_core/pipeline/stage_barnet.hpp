// What the bar-net stage keeps (barnet-driven-skinning; docs/barnet.md): the
// rig's bar-nets, up to kMaxBarnets.
#pragma once

#include <cstdint>

#include "layer_format.hpp"
#include "sim_core/barnet/barnet_section.hpp"
#include "sim_core/barnet/barnet_state.hpp"
#include "stage.hpp"

namespace sinew::pipeline {

using barnet::kMaxBarnets;

struct BarnetLayers {
  barnet::BarnetModel net[kMaxBarnets];
  uint32_t count = 0;
};

struct BarnetRun {
  barnet::BarnetState net[kMaxBarnets];
  uint32_t count = 0;  // nets running (0 when switched off)
};

struct BarnetOptions {};

template <>
struct StageData<Stage::kBarnet> {
  using Layers = BarnetLayers;
  using Run = BarnetRun;
  using Options = BarnetOptions;
  static constexpr std::array<const layer::SectionDescriptor*, 1> sections = {&barnet::kBarnetSection};
  static constexpr std::array<StageOption, 0> options = {};  // none
  static constexpr bool parallel = false;
};

}  // namespace sinew::pipeline
