// The shape every layer section of the rig format shares (docs/rig-format.md,
// "Layer sections"), and the descriptor each layer gives of its own section
// in sim_core/<layer>/<layer>_section.hpp: its arrays in order (name,
// element size, maximum count) and its versions (params record size, how
// many of those arrays). The runtime loader (sim_core/pipeline/
// layer_loader.cpp) checks a section against the descriptor and the rig
// compiler's writer (host_tools/layers/sections/layer_writer.cpp) writes
// from it, so the two cannot list a section's fields differently.
//
//   LayerSectionHeader   32 bytes
//   params               params_size bytes, the layer's fixed record, padded
//                        with zeros to a multiple of 8
//   LayerArrayEntry[n]   16 bytes each: where each of the layer's arrays is
//   arrays               each at a multiple of 8 from the section start
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace sinew::layer {

inline constexpr uint32_t kLayerSectionVersion = 1;

struct LayerSectionHeader {  // 32 bytes at the start of every layer section
  uint32_t layer_version;    // one of the section's SectionVersion::version
  uint32_t params_size;      // bytes of the params record (unpadded); must equal the version's
  uint32_t array_count;      // entries of the array table; must equal the version's
  uint32_t rate_hz;          // tick rate the gains were built for; 0 when they do not depend on it
  uint32_t reserved[4];      // 0 written; not checked
};
static_assert(sizeof(LayerSectionHeader) == 32);

struct LayerArrayEntry {  // 16 bytes
  uint32_t offset;        // from the section start, a multiple of 8
  uint32_t count;         // elements
  uint32_t element_size;  // bytes per element; must equal the descriptor's
  uint32_t reserved;
};
static_assert(sizeof(LayerArrayEntry) == 16);

// One array of a section, in section order.
struct SectionArray {
  const char* name;       // as the loader's messages and docs/rig-format.md name it
  uint32_t element_size;  // bytes per element
  uint32_t max_count;     // the layer's documented maximum
};

// One version of a section: its params record and the first array_count
// arrays of the section's array list (a later version appends arrays).
struct SectionVersion {
  uint32_t version;
  uint32_t params_size;
  uint32_t array_count;
};

// A section's descriptor: the arrays of its newest version and every
// version a loader accepts.
struct SectionDescriptor {
  uint32_t id;       // the section's four-character id
  const char* name;  // e.g. "SPHJ"
  std::span<const SectionArray> arrays;
  std::span<const SectionVersion> versions;
  uint32_t max_instances;  // how many sections of this id one blob may carry
  uint32_t needs = 0;      // the id of a section it cannot be loaded without, or 0

  // The version's row, or null when the loader does not know it.
  constexpr const SectionVersion* find(uint32_t version) const {
    for (const SectionVersion& v : versions)
      if (v.version == version) return &v;
    return nullptr;
  }
};

// Where an array sits in a section's array list, found by name at compile
// time: a loader reads `array_ref(kArrays, "ball_rest")` instead of an index,
// and checks element_size against the type it reads it as (see
// layer_loader.cpp's `named`). kNoArray: the list has no such name.
inline constexpr uint32_t kNoArray = 0xFFFFFFFFu;
struct ArrayRef {
  uint32_t index;
  uint32_t element_size;
};
constexpr ArrayRef array_ref(std::span<const SectionArray> arrays, std::string_view name) {
  for (uint32_t i = 0; i < arrays.size(); ++i)
    if (name == arrays[i].name) return {i, arrays[i].element_size};
  return {kNoArray, 0};
}

}  // namespace sinew::layer
