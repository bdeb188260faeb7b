// A layer section of a rig blob after its structure was checked against its
// descriptor (layer_format.hpp; layer_loader.cpp checks every section before
// any is read): where its params and arrays are, and the typed readers the
// stages' loaders (stage_<name>_section.cpp) take their models from.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>

#include "layer_sections.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::pipeline {

struct SectionView {
  uint32_t id = 0, instance = 0;
  const uint8_t* base = nullptr;  // section start (in the blob, then in the arena)
  uint32_t size = 0;
  LayerSectionHeader header{};
  LayerArrayEntry arrays[kMaxLayerArrays] = {};
};

// "rig blob: <SECT>#<instance>.<field>[<index>]: <problem> (<value>)"; no
// field when field is empty, no index when index < 0.
rig::LoadStatus section_fail(rig::LoadError e, uint32_t id, uint32_t instance, const char* field, int64_t index,
                             const char* what, int64_t value = 0, bool show_value = false);
inline rig::LoadStatus section_fail(rig::LoadError e, const SectionView& v, const char* field, int64_t index,
                                    const char* what, int64_t value = 0, bool show_value = false) {
  return section_fail(e, v.id, v.instance, field, index, what, value, show_value);
}

// "rig blob: <SECT>#<instance>: <message>": a layer validator's message.
rig::LoadStatus section_layer_fail(rig::LoadError e, const SectionView& v, const char* message);

template <typename T>
std::span<const T> section_array(const SectionView& v, uint32_t i) {
  static_assert(alignof(T) <= 8, "arrays are 8-byte aligned");
  const LayerArrayEntry& e = v.arrays[i];
  if (e.count == 0) return {};
  // The arena bytes were written by memcpy, which creates implicit objects.
  return {static_cast<const T*>(static_cast<const void*>(v.base + e.offset)), e.count};
}

// The array the section's descriptor names `R` (layer::array_ref), read as
// T: a name the descriptor lacks, or a T of another size than the
// descriptor's element, does not compile, so a loader cannot drift from
// the descriptor the writer also reads.
template <typename T, layer::ArrayRef R>
std::span<const T> named(const SectionView& v) {
  static_assert(R.index != layer::kNoArray, "the section's descriptor lists no array of that name");
  static_assert(R.element_size == sizeof(T), "the descriptor's element size differs from the type read");
  return section_array<T>(v, R.index);
}

// The section's params record, read as P (its version's record).
template <typename P>
P params_of(const SectionView& v) {
  P p{};
  std::memcpy(&p, v.base + sizeof(LayerSectionHeader), sizeof(P));
  return p;
}

}  // namespace sinew::pipeline
