// The BNET section of the rig format: one bar-net (may repeat). Its params
// record, versions and arrays, read by the runtime loader and the rig
// compiler's writer alike (sim_core/layer/section_format.hpp).
//
// Arrays: inverse_bind, nodes, bars, loads, triangles, wrap. Version 1:
// loads read joint angles only, q is constant; the last params word is 0
// written, not checked. Version 2 adds the inputs: the last params word is
// the count of external inputs (EXTI) the net was built against, loads may
// read them (LoadRecord::input from input_count on), and a 7th array,
// q_inputs (ForceDensityInput), scales runs of bars' q from them. Writers
// emit version 1 for a net with neither, so those rigs keep their bytes; a
// version-1-only loader refuses version 2.
#pragma once

#include <cstdint>

#include "barnet_model.hpp"
#include "sim_core/layer/section_format.hpp"

namespace sinew::barnet {

inline constexpr uint32_t kSectionBarnet = 0x54454E42u;  // "BNET"
inline constexpr uint32_t kMaxBarnets = 8;               // BNET sections one blob may carry

struct BarnetSectionParams {
  uint32_t joint_count, input_count, vertex_count;
  uint32_t external_count;  // version 2; version 1: reserved, 0
};
static_assert(sizeof(ForceDensityInput) == 16);
static_assert(sizeof(NodeRecord) == 40 && sizeof(BarRecord) == 12 && sizeof(LoadRecord) == 28 &&
              sizeof(ControlTriangle) == 12 && sizeof(WrapRecord) == 24);
inline constexpr uint32_t kBarnetArrays = 6;
inline constexpr uint32_t kBarnetSectionVersion2 = 2;
inline constexpr uint32_t kBarnetArraysV2 = 7;

inline constexpr layer::SectionArray kBarnetSectionArrays[kBarnetArraysV2] = {
    {"inverse_bind", sizeof(fx::Mat34), kMaxJoints},
    {"nodes", sizeof(NodeRecord), kMaxNodes},
    {"bars", sizeof(BarRecord), kMaxBars},
    {"loads", sizeof(LoadRecord), kMaxLoads},
    {"triangles", sizeof(ControlTriangle), kMaxTriangles},
    {"wrap", sizeof(WrapRecord), kMaxWrapVertices},
    {"q_inputs", sizeof(ForceDensityInput), kMaxForceDensityInputs},  // version 2
};
inline constexpr layer::SectionVersion kBarnetSectionVersions[] = {
    {layer::kLayerSectionVersion, sizeof(BarnetSectionParams), kBarnetArrays},
    {kBarnetSectionVersion2, sizeof(BarnetSectionParams), kBarnetArraysV2},
};
inline constexpr layer::SectionDescriptor kBarnetSection = {kSectionBarnet, "BNET", kBarnetSectionArrays,
                                                            kBarnetSectionVersions, kMaxBarnets};

}  // namespace sinew::barnet
