// The physical layers a rig blob carries, loaded: each layer's immutable
// model, its spans pointing into a caller-provided arena sized by
// layers_validate(). Loading validates every layer section (bounds, element
// sizes, counts, then the layer's own validator against the rig) before any
// span is handed out. Nothing here allocates.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "layer_format.hpp"
#include "sim_core/rig/rig.hpp"
#include "stage_data.hpp"

namespace sinew::pipeline {

// Each stage's loaded models (StageData<stage>::Layers, stage_<name>.hpp),
// one member per line of stage_list.hpp named as the stage
// (layers.<stage>). The pipeline's own: the external inputs and the rate.
struct LayerSet {
  std::span<const ExternalInputRecord> external;
#define SINEW_STAGE_LAYERS(name, enumerator, sections, doc) \
  [[no_unique_address]] StageData<Stage::enumerator>::Layers name;
  SINEW_STAGE_LIST(SINEW_STAGE_LAYERS)
#undef SINEW_STAGE_LAYERS
  // The tick rate the rate-dependent sections were built for; 0 when
  // no section depends on the rate.
  uint32_t rate_hz = 0;

  uint32_t external_count() const { return static_cast<uint32_t>(external.size()); }
  // No layer beyond skinning (the stage table's compiled counts).
  bool empty() const;
};

// Validates the layer sections of a blob that rig_init accepted for `rig`,
// and reports the arena bytes layers_init needs (0 for a blob without layers).
// Errors use rig::LoadStatus and name the section, its instance and field.
rig::LoadStatus layers_validate(const rig::Rig& rig, const uint8_t* blob, size_t size, size_t* arena_bytes);

// Validates, then copies the layer sections into `arena` (8-byte aligned, at
// least layers_validate's bytes) and points `out` at them. The blob may be
// released afterwards; `rig` must outlive `out`.
rig::LoadStatus layers_init(const rig::Rig& rig, const uint8_t* blob, size_t size, void* arena, size_t arena_bytes,
                            LayerSet* out);

// The index of a named external input, or kNoExternalInput.
uint32_t find_external_input(const LayerSet& layers, const char* name);

}  // namespace sinew::pipeline
