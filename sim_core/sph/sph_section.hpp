// The SPHJ section of the rig format: one SPH elastic joint (may repeat).
// Its params records, versions and arrays, read by the runtime loader and
// the rig compiler's writer alike (sim_core/layer/section_format.hpp).
//
// Arrays, in order: rest_local x, y, z (Len), rest_model x, y, z (Len),
// bone (u8), skin_vertex (u32), skin_rest x, y, z (Len).
//
// Layer version 1: SphSectionParamsV1, the SphParams fields before
// tension_gain; it loads with tension_gain = 0 (no surface tension). Layer
// version 2: SphSectionParams, the whole SphParams. Both records are 84
// bytes. Writers emit version 1 whenever tension_gain is 0, so rigs without
// surface tension keep their bytes; a loader that knows only version 1
// refuses a version 2 section (kBadVersion).
#pragma once

#include <cstddef>
#include <cstdint>

#include "sim_core/layer/section_format.hpp"
#include "sph_model.hpp"

namespace sinew::sph {

inline constexpr uint32_t kSectionSphJoint = 0x4A485053u;  // "SPHJ"
inline constexpr uint32_t kMaxSphJoints = 8;               // SPHJ sections one blob may carry

inline constexpr uint32_t kSphParamsV1Bytes = 44;  // SphParams up to grid_radius
struct SphSectionParamsV1 {
  uint8_t params[kSphParamsV1Bytes];  // the first 44 bytes of sph::SphParams
  SphJoint joint;
  uint32_t force_input;  // index into EXTI of the force at the load point, or kNoExternalInput
  uint32_t reserved;
};
struct SphSectionParams {
  SphParams params;
  SphJoint joint;
  uint32_t force_input;  // as in version 1
};
static_assert(sizeof(SphParams) == 48 && offsetof(SphParams, tension_gain) == kSphParamsV1Bytes &&
              sizeof(SphJoint) == 32);
static_assert(sizeof(SphSectionParamsV1) == 84 && sizeof(SphSectionParams) == 84);
inline constexpr uint32_t kSphSectionVersion2 = 2;
inline constexpr uint32_t kSphArrays = 11;

inline constexpr layer::SectionArray kSphSectionArrays[kSphArrays] = {
    {"rest_local_x", sizeof(fx::Len), kMaxParticles},
    {"rest_local_y", sizeof(fx::Len), kMaxParticles},
    {"rest_local_z", sizeof(fx::Len), kMaxParticles},
    {"rest_model_x", sizeof(fx::Len), kMaxParticles},
    {"rest_model_y", sizeof(fx::Len), kMaxParticles},
    {"rest_model_z", sizeof(fx::Len), kMaxParticles},
    {"bone", 1, kMaxParticles},
    {"skin_vertex", 4, kMaxSkinVertices},
    {"skin_rest_x", sizeof(fx::Len), kMaxSkinVertices},
    {"skin_rest_y", sizeof(fx::Len), kMaxSkinVertices},
    {"skin_rest_z", sizeof(fx::Len), kMaxSkinVertices},
};
inline constexpr layer::SectionVersion kSphSectionVersions[] = {
    {layer::kLayerSectionVersion, sizeof(SphSectionParamsV1), kSphArrays},
    {kSphSectionVersion2, sizeof(SphSectionParams), kSphArrays},
};
inline constexpr layer::SectionDescriptor kSphSection = {kSectionSphJoint, "SPHJ", kSphSectionArrays,
                                                         kSphSectionVersions, kMaxSphJoints};

}  // namespace sinew::sph
