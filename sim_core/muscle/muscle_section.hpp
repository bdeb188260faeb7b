// The MUSC section of the rig format: every muscle and primitive (at most
// one). Its params record, versions and arrays, read by the runtime loader
// and the rig compiler's writer alike (sim_core/layer/section_format.hpp).
//
// Arrays: muscles (MuscleRecord), primitives (PrimitiveRecord). Layer
// version 2 appends deformations (PrimitiveDeformation, empty or one per
// primitive: Barr's taper, twist and bend); writers emit version 1 while no
// primitive is deformed, so rigs without deformations keep their bytes.
// Version 3 appends shapes (MuscleShape, empty or one per muscle: §4.2 end
// axes from bone normals, Table 1 slice edits and the variable pivot);
// deformations is then present and may be empty; written only when a
// muscle has a non-default shape. Version 4 appends exponents
// (PrimitiveExponents, empty or one per primitive: Barr's two superquadric
// exponents, Q16.16 in [1, 16]); deformations and shapes are then present
// and may be empty; written only when some primitive's exponents are not an
// equal 2, 4 or 8 (its record's exponent is then 0). A loader refuses a
// version it does not know (kBadVersion); older versions load with the
// defaults of what they lack.
#pragma once

#include <cstdint>

#include "muscle_model.hpp"
#include "sim_core/layer/section_format.hpp"

namespace sinew::muscle {

inline constexpr uint32_t kSectionMuscles = 0x4353554Du;  // "MUSC"

struct MusclesSectionParams {
  uint32_t joint_count, ring_vertices;
};
static_assert(sizeof(MuscleRecord) == 184 && sizeof(PrimitiveRecord) == 36 && sizeof(PrimitiveDeformation) == 16 &&
              sizeof(MuscleShape) == 440 && sizeof(PrimitiveExponents) == 8);
inline constexpr uint32_t kMusclesArrays = 2;
inline constexpr uint32_t kMusclesSectionVersion2 = 2;
inline constexpr uint32_t kMusclesArraysV2 = 3;
inline constexpr uint32_t kMusclesSectionVersion3 = 3;
inline constexpr uint32_t kMusclesArraysV3 = 4;
inline constexpr uint32_t kMusclesSectionVersion4 = 4;
inline constexpr uint32_t kMusclesArraysV4 = 5;

inline constexpr layer::SectionArray kMusclesSectionArrays[kMusclesArraysV4] = {
    {"muscles", sizeof(MuscleRecord), kMaxMuscles},
    {"primitives", sizeof(PrimitiveRecord), kMaxPrimitives},
    {"deformations", sizeof(PrimitiveDeformation), kMaxPrimitives},  // version 2 on
    {"shapes", sizeof(MuscleShape), kMaxMuscles},                    // version 3 on
    {"exponents", sizeof(PrimitiveExponents), kMaxPrimitives},       // version 4
};
inline constexpr layer::SectionVersion kMusclesSectionVersions[] = {
    {layer::kLayerSectionVersion, sizeof(MusclesSectionParams), kMusclesArrays},
    {kMusclesSectionVersion2, sizeof(MusclesSectionParams), kMusclesArraysV2},
    {kMusclesSectionVersion3, sizeof(MusclesSectionParams), kMusclesArraysV3},
    {kMusclesSectionVersion4, sizeof(MusclesSectionParams), kMusclesArraysV4},
};
inline constexpr layer::SectionDescriptor kMusclesSection = {kSectionMuscles, "MUSC", kMusclesSectionArrays,
                                                             kMusclesSectionVersions, 1};

}  // namespace sinew::muscle
