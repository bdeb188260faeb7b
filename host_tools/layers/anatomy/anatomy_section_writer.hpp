// The anatomy layer's two sections, muscles (sim_core/muscle/muscle_section.hpp)
// and skin (sim_core/elastic_skin/skin_section.hpp), from the builder's models.
#pragma once

#include <cstdint>
#include <span>

#include "host_tools/layers/sections/layer_section.hpp"
#include "sim_core/elastic_skin/skin_section.hpp"
#include "sim_core/muscle/muscle_section.hpp"
#include "sim_core/pipeline/layer_format.hpp"

namespace sinew::layers {

inline constexpr uint32_t kNoBaseAcceleration[3] = {pipeline::kNoExternalInput, pipeline::kNoExternalInput,
                                                    pipeline::kNoExternalInput};

LayerSection muscles_section(const ::sinew::muscle::MuscleModel& model);
// base_acceleration: the EXTI indices of the base's acceleration x, y, z
// (pipeline::kNoExternalInput: none); any set makes it a version 5 section.
LayerSection skin_section(const ::sinew::elastic_skin::SkinModel& model, std::span<const uint32_t> region = {},
                          std::span<const fx::Unit> region_weight = {},
                          const uint32_t (&base_acceleration)[3] = kNoBaseAcceleration);

}  // namespace sinew::layers
