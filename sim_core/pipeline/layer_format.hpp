// Layer sections of the binary rig format, version 1.1 (docs/rig-format.md,
// "Layer sections"): the physical layers a rig compiler built offline, in
// fixed point, so the board only loads and validates them.
//
// A 1.0 loader skips these sections (unknown ids). Every layer section has
// the same shape (sim_core/layer/section_format.hpp), so one reader
// bounds-checks all of them against each section's descriptor, which lives
// beside its layer: sim_core/sph/sph_section.hpp (SPHJ),
// sim_core/metaballs/metaballs_section.hpp (MBAL),
// sim_core/muscle/muscle_section.hpp (MUSC),
// sim_core/elastic_skin/skin_section.hpp (SKIN),
// sim_core/barnet/barnet_section.hpp (BNET); EXTI is the pipeline's own
// (below). kLayerSections lists them for the loader and the writer.
//
// Records are the runtime models' own plain structs (little-endian, int32
// based, no pointers, no implicit padding: every byte is a zero-initialised
// member, so a blob's bytes are the same from every compiler); their sizes
// are pinned by static_asserts beside them so a layout change cannot go
// unnoticed.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sim_core/barnet/barnet_section.hpp"
#include "sim_core/elastic_skin/skin_section.hpp"
#include "sim_core/layer/section_format.hpp"
#include "sim_core/metaballs/metaballs_section.hpp"
#include "sim_core/muscle/muscle_section.hpp"
#include "sim_core/rig/rig_format.hpp"
#include "sim_core/sph/sph_section.hpp"

namespace sinew::pipeline {

enum LayerSectionId : uint32_t {
  kSectionSphJoint = sph::kSectionSphJoint,                 // "SPHJ": one SPH elastic joint; may repeat
  kSectionMetaballs = metaballs::kSectionMetaballs,         // "MBAL": the metaballs skin; at most one
  kSectionMuscles = muscle::kSectionMuscles,                // "MUSC": every muscle and primitive; at most one
  kSectionElasticSkin = elastic_skin::kSectionElasticSkin,  // "SKIN": the elastic skin; needs MUSC; at most one
  kSectionBarnet = barnet::kSectionBarnet,                  // "BNET": one bar-net; may repeat
  kSectionExternalInputs = 0x49545845u,                     // "EXTI": ExternalInputRecord[]; at most one
};

using barnet::kMaxBarnets;
using layer::kLayerSectionVersion;
using layer::LayerArrayEntry;
using layer::LayerSectionHeader;
using sph::kMaxSphJoints;
inline constexpr uint32_t kMaxExternalInputs = 64;
inline constexpr uint32_t kMaxLayerArrays = 32;
inline constexpr uint32_t kUnitBytes = 16;

// What an external input measures; its values are Q16.16 in that unit.
enum class InputQuantity : uint32_t {
  kForce = 0,         // newtons
  kLength = 1,        // metres
  kAngle = 2,         // degrees
  kScalar = 3,        // dimensionless
  kAcceleration = 4,  // metres / s^2 (the rig's base: the elastic skin's a_base)
};

// An input the rig's layers read besides its joint DOFs (e.g. a force
// sensor): fed, health-checked, held and logged like a joint input; only the
// layer that names it reads it. Its index in the runtime's input array is the
// rig's input_count plus its position in EXTI.
struct ExternalInputRecord {   // 64 bytes
  char name[rig::kNameBytes];  // NUL-terminated, unique, not a joint DOF name
  char unit[kUnitBytes];       // NUL-terminated, e.g. "N"
  uint32_t quantity;           // InputQuantity
  int32_t min, max;            // accepted range, Q16.16 in the unit; min < max
  uint32_t reserved;
};
static_assert(sizeof(ExternalInputRecord) == 64);

inline constexpr uint32_t kNoExternalInput = 0xFFFFFFFFu;

// The layers' section records and versions, under the names the loader and
// the writer use.
using barnet::BarnetSectionParams;
using barnet::kBarnetArrays;
using barnet::kBarnetArraysV2;
using barnet::kBarnetSectionVersion2;
using elastic_skin::kSkinArrays;
using elastic_skin::kSkinSectionVersion2;
using elastic_skin::kSkinSectionVersion3;
using elastic_skin::kSkinSectionVersion4;
using elastic_skin::kSkinSectionVersion5;
using elastic_skin::kSkinSolverBytesV2;
using elastic_skin::SkinSectionParams;
using elastic_skin::SkinSectionParamsV2;
using elastic_skin::SkinSectionParamsV3;
using elastic_skin::SkinSectionParamsV5;
using metaballs::kMetaballsArrays;
using metaballs::kMetaballsArraysV2;
using metaballs::kMetaballsSectionVersion2;
using metaballs::MetaballsSectionParams;
using muscle::kMusclesArrays;
using muscle::kMusclesArraysV2;
using muscle::kMusclesArraysV3;
using muscle::kMusclesArraysV4;
using muscle::kMusclesSectionVersion2;
using muscle::kMusclesSectionVersion3;
using muscle::kMusclesSectionVersion4;
using muscle::MusclesSectionParams;
using sph::kSphArrays;
using sph::kSphParamsV1Bytes;
using sph::kSphSectionVersion2;
using sph::SphSectionParams;
using sph::SphSectionParamsV1;

// EXTI params: none (params_size 0). Array: ExternalInputRecord[].
inline constexpr uint32_t kExternalInputArrays = 1;
inline constexpr layer::SectionArray kExternalInputArraysList[kExternalInputArrays] = {
    {"inputs", sizeof(ExternalInputRecord), kMaxExternalInputs},
};
inline constexpr layer::SectionVersion kExternalInputVersions[] = {{kLayerSectionVersion, 0, kExternalInputArrays}};
inline constexpr layer::SectionDescriptor kExternalInputSection = {kSectionExternalInputs, "EXTI",
                                                                   kExternalInputArraysList, kExternalInputVersions, 1};

// Every layer section the loader knows, with its descriptor.
inline constexpr const layer::SectionDescriptor* kLayerSections[] = {
    &sph::kSphSection,           &metaballs::kMetaballsSection, &muscle::kMusclesSection,
    &elastic_skin::kSkinSection, &barnet::kBarnetSection,       &kExternalInputSection,
};

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

}  // namespace sinew::pipeline
