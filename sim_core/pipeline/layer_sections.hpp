// Every layer section the loader knows, with its descriptor: each stage's
// (StageData::sections, stage_<name>.hpp) in stage order, then the
// pipeline's own EXTI (layer_format.hpp). Expanded from stage_list.hpp, so
// a layer's sections are listed where its stage declares them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "layer_format.hpp"
#include "stage_data.hpp"

namespace sinew::pipeline {

#define SINEW_STAGE_SECTION_COUNT(name, enumerator, spec_sections, doc) +StageData<Stage::enumerator>::sections.size()
inline constexpr size_t kLayerSectionKinds = 1 SINEW_STAGE_LIST(SINEW_STAGE_SECTION_COUNT);
#undef SINEW_STAGE_SECTION_COUNT

inline constexpr std::array<const layer::SectionDescriptor*, kLayerSectionKinds> kLayerSections = [] {
  std::array<const layer::SectionDescriptor*, kLayerSectionKinds> all{};
  size_t n = 0;
#define SINEW_STAGE_SECTIONS(name, enumerator, spec_sections, doc) \
  for (const layer::SectionDescriptor* d : StageData<Stage::enumerator>::sections) all[n++] = d;
  SINEW_STAGE_LIST(SINEW_STAGE_SECTIONS)
#undef SINEW_STAGE_SECTIONS
  all[n] = &kExternalInputSection;
  return all;
}();

// The most layer sections one blob may carry, every id at its limit.
inline constexpr uint32_t kMaxLayerSectionCount = [] {
  uint32_t n = 0;
  for (const layer::SectionDescriptor* d : kLayerSections) n += d->max_instances;
  return n;
}();

// The descriptor of a section id, or null.
constexpr const layer::SectionDescriptor* find_layer_section(uint32_t id) {
  for (const layer::SectionDescriptor* d : kLayerSections)
    if (d->id == id) return d;
  return nullptr;
}

// No two sections share an id.
static_assert(
    [] {
      for (size_t i = 0; i < kLayerSections.size(); ++i)
        for (size_t j = i + 1; j < kLayerSections.size(); ++j)
          if (kLayerSections[i]->id == kLayerSections[j]->id) return false;
      return true;
    }(),
    "two layer sections share an id");

}  // namespace sinew::pipeline
