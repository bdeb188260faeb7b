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

namespace sinew::pipeline {

struct SphJointLayer {
  sph::SphModel model;
  uint32_t force_input = kNoExternalInput;  // index into external, or kNoExternalInput
};

struct LayerSet {
  std::span<const ExternalInputRecord> external;
  SphJointLayer sph[kMaxSphJoints];
  uint32_t sph_count = 0;
  bool has_metaballs = false;
  metaballs::MetaballModel metaballs;
  bool has_muscles = false;
  muscle::MuscleModel muscles;
  bool has_skin = false;
  elastic_skin::SkinModel skin;
  std::span<const uint32_t> skin_region;         // vertices the skin displaces (empty: all)
  std::span<const fx::Unit> skin_region_weight;  // their weights, Q2.30 in (0, 1]
  // The external inputs of the base's acceleration, x, y, z (SKIN version 5),
  // or kNoExternalInput: the dynamic skin then feels no base motion.
  uint32_t skin_base_acceleration[3] = {kNoExternalInput, kNoExternalInput, kNoExternalInput};
  barnet::BarnetModel barnet[kMaxBarnets];
  uint32_t barnet_count = 0;
  // The tick rate the rate-dependent sections were built for (SPH); 0 when
  // no section depends on the rate.
  uint32_t rate_hz = 0;

  uint32_t external_count() const { return static_cast<uint32_t>(external.size()); }
  bool empty() const { return sph_count == 0 && !has_metaballs && !has_muscles && barnet_count == 0; }
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
