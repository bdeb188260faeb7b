// The SKIN section of the rig format: the elastic skin (at most one; needs
// MUSC). Its params records, versions and arrays, read by the runtime
// loader and the rig compiler's writer alike
// (sim_core/layer/section_format.hpp).
//
// Arrays: anchors, anchor_stiffness, fat, edges, bands, then the skin's
// support region: region_vertex (u32, ascending) and region_weight (Unit,
// (0, 1]): the relaxed skin displaces those vertices by weight x (relaxed -
// skinned); every other vertex keeps its skinned position bit for bit. Both
// empty: the whole skin, weight 1.
//
// Version 1: SkinSectionParams; the solver is SkinSolverParams{} (static
// relaxation, no tolerance, no global fat). Version 2 appends the solver
// record's first 52 bytes (SkinSectionParamsV2: dynamic mode, tolerance,
// global fat). Version 3 carries the whole solver record, whose last member,
// edge_damping, version 2 lacks (it then reads 0). Version 4: the version 3
// record whose solver.fat_normal (the byte after mode, reserved before) may
// be FatNormal::kSurface; older versions read that byte as 0 (the anchor
// normal). Version 5: the version 3 record followed by the three external
// inputs (EXTI indices, or kNoExternalInput) that measure the acceleration
// of the frame the bones are given in, x, y, z in the rig's axes: the
// dynamic skin feels -a_base (LEMAN §3). Version 6: the version 5 record
// followed by SkinSurfaceParams (the dynamic mode's integrator: LEMAN
// §6.11's relaxation with the §3 surface's bend, §5.3's air pressure and
// Platt-Barr reactions); older versions load with SkinSurfaceParams{} (the
// explicit integrator). Writers emit the lowest version
// that holds the model, so rigs keep their bytes; a loader refuses a version
// it does not know (kBadVersion). The skin's faces are the rig's triangles
// (SkinModel::triangles), not stored again.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sim_core/layer/section_format.hpp"
#include "sim_core/muscle/muscle_section.hpp"
#include "skin_model.hpp"

namespace sinew::elastic_skin {

inline constexpr uint32_t kSectionElasticSkin = 0x4E494B53u;  // "SKIN"

struct SkinSectionParams {
  uint32_t joint_count, vertex_count;
  SkinParams params;
};
inline constexpr uint32_t kSkinSolverBytesV2 = 52;
struct SkinSectionParamsV2 {
  uint32_t joint_count, vertex_count;
  SkinParams params;
  uint8_t solver[kSkinSolverBytesV2];  // the first 52 bytes of SkinSolverParams
};
struct SkinSectionParamsV3 {
  uint32_t joint_count, vertex_count;
  SkinParams params;
  SkinSolverParams solver;
};
struct SkinSectionParamsV5 {
  SkinSectionParamsV3 v3;
  uint32_t base_acceleration_input[3];
  uint32_t reserved;
};
inline constexpr uint32_t kSkinSectionVersion2 = 2;
inline constexpr uint32_t kSkinSectionVersion3 = 3;
inline constexpr uint32_t kSkinSectionVersion4 = 4;
struct SkinSectionParamsV6 {
  SkinSectionParamsV5 v5;
  SkinSurfaceParams surface;
};
inline constexpr uint32_t kSkinSectionVersion5 = 5;
inline constexpr uint32_t kSkinSectionVersion6 = 6;
static_assert(sizeof(SkinParams) == 28 && sizeof(Anchor) == 80 && sizeof(Edge) == 16 && sizeof(RubberBand) == 20 &&
              sizeof(SkinSolverParams) == 56 && sizeof(SkinSectionParamsV2) == 88 &&
              sizeof(SkinSectionParamsV3) == 92 && sizeof(SkinSectionParamsV5) == 108 &&
              sizeof(SkinSurfaceParams) == 16 && sizeof(SkinSectionParamsV6) == 124 &&
              offsetof(SkinSolverParams, edge_damping) == kSkinSolverBytesV2);
inline constexpr uint32_t kSkinArrays = 7;

inline constexpr layer::SectionArray kSkinSectionArrays[kSkinArrays] = {
    {"anchors", sizeof(Anchor), kMaxVertices},   {"anchor_stiffness", 4, kMaxVertices},
    {"fat", sizeof(fx::Len), kMaxVertices},      {"edges", sizeof(Edge), 4 * kMaxVertices},
    {"bands", sizeof(RubberBand), kMaxVertices}, {"region_vertex", 4, kMaxVertices},
    {"region_weight", 4, kMaxVertices},
};
inline constexpr layer::SectionVersion kSkinSectionVersions[] = {
    {layer::kLayerSectionVersion, sizeof(SkinSectionParams), kSkinArrays},
    {kSkinSectionVersion2, sizeof(SkinSectionParamsV2), kSkinArrays},
    {kSkinSectionVersion3, sizeof(SkinSectionParamsV3), kSkinArrays},
    {kSkinSectionVersion4, sizeof(SkinSectionParamsV3), kSkinArrays},
    {kSkinSectionVersion5, sizeof(SkinSectionParamsV5), kSkinArrays},
    {kSkinSectionVersion6, sizeof(SkinSectionParamsV6), kSkinArrays},
};
inline constexpr layer::SectionDescriptor kSkinSection = {kSectionElasticSkin,  "SKIN", kSkinSectionArrays,
                                                          kSkinSectionVersions, 1,      muscle::kSectionMuscles};

}  // namespace sinew::elastic_skin
