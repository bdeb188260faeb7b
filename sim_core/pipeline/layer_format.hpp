// Layer sections of the binary rig format, version 1.1 (docs/rig-format.md,
// "Layer sections"): the physical layers a rig compiler built offline, in
// fixed point, so the board only loads and validates them.
//
// A 1.0 loader skips these sections (unknown ids). Every layer section has
// the same shape (sim_core/layer/section_format.hpp), so one reader
// bounds-checks all of them against each section's descriptor, which lives
// beside its layer (sim_core/<layer>/<layer>_section.hpp); each stage
// names its sections (StageData::sections, stage_<name>.hpp) and
// layer_sections.hpp lists them all for the loader. EXTI, the external
// inputs, is the pipeline's own (below).
//
// Records are the runtime models' own plain structs (little-endian, int32
// based, no pointers, no implicit padding: every byte is a zero-initialised
// member, so a blob's bytes are the same from every compiler); their sizes
// are pinned by static_asserts beside them so a layout change cannot go
// unnoticed.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sim_core/layer/section_format.hpp"
#include "sim_core/rig/rig_format.hpp"

namespace sinew::pipeline {

// "EXTI": ExternalInputRecord[]; at most one.
inline constexpr uint32_t kSectionExternalInputs = 0x49545845u;

using layer::kLayerSectionVersion;
using layer::LayerArrayEntry;
using layer::LayerSectionHeader;

inline constexpr uint32_t kMaxExternalInputs = 64;
inline constexpr uint32_t kMaxLayerArrays = 32;
inline constexpr uint32_t kUnitBytes = 16;

// What an external input measures; its values are Q16.16 in that unit.
enum class InputQuantity : uint32_t {
  kForce = 0,         // newtons
  kLength = 1,        // metres
  kAngle = 2,         // degrees
  kScalar = 3,        // dimensionless
  kAcceleration = 4,  // metres / s^2 (e.g. the rig's base)
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

// EXTI params: none (params_size 0). Array: ExternalInputRecord[].
inline constexpr uint32_t kExternalInputArrays = 1;
inline constexpr layer::SectionArray kExternalInputArraysList[kExternalInputArrays] = {
    {"inputs", sizeof(ExternalInputRecord), kMaxExternalInputs},
};
inline constexpr layer::SectionVersion kExternalInputVersions[] = {{kLayerSectionVersion, 0, kExternalInputArrays}};
inline constexpr layer::SectionDescriptor kExternalInputSection = {kSectionExternalInputs, "EXTI",
                                                                   kExternalInputArraysList, kExternalInputVersions, 1};

}  // namespace sinew::pipeline
