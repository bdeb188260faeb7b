// The MBAL section of the rig format: the metaballs skin (at most one). Its
// params record, versions and arrays, read by the runtime loader and the
// rig compiler's writer alike (sim_core/layer/section_format.hpp). The
// header's rate_hz is the model's jiggle_rate_hz (0: per-step gains).
//
// Layer version 1: the first 25 arrays, no action lines. Layer version 2
// appends two: action_lines (ActionLine) and action_balls (ActionBall).
// Writers emit version 1 whenever the model has no action line, so rigs
// without them keep their bytes; a loader that knows only version 1 refuses
// a version 2 section (kBadVersion). Layer version 3 has version 2's arrays
// and meanings a version 2 reader would take wrongly: a model with
// jiggle_rate_hz > 0 carries stretch pairs whose stiffness is the coupling
// (omega_c / rate)^2 of metaballs::coupling_stiffness, and overlap records
// may join two bones that share no joint (OverlapRecord, joint ==
// kNoJoint). Writers emit it only for such a model.
#pragma once

#include <cstdint>

#include "model.hpp"
#include "sim_core/layer/section_format.hpp"

namespace sinew::metaballs {

inline constexpr uint32_t kSectionMetaballs = 0x4C41424Du;  // "MBAL"

struct MetaballsSectionParams {
  uint32_t joint_count, vertex_count;
  uint32_t pbd_iterations;
  fx::Unit jiggle_damping;
  uint32_t smoothing_passes;
  fx::Unit smoothing_rate;
};
static_assert(sizeof(BallPair) == 20 && sizeof(BulgeRecord) == 12 && sizeof(JointBall) == 24 &&
              sizeof(OverlapRecord) == 64);
static_assert(sizeof(ActionLine) == 32 && sizeof(ActionBall) == 16);
inline constexpr uint32_t kMetaballsArrays = 25;
inline constexpr uint32_t kMetaballsSectionVersion2 = 2;
inline constexpr uint32_t kMetaballsArraysV2 = 27;
inline constexpr uint32_t kMetaballsSectionVersion3 = 3;

inline constexpr layer::SectionArray kMetaballsSectionArrays[kMetaballsArraysV2] = {
    {"inverse_bind", sizeof(fx::Mat34), kMaxJoints},
    {"ball_rest", sizeof(fx::Vec3), kMaxBalls},
    {"ball_radius", sizeof(fx::Len), kMaxBalls},
    {"ball_bone", 2, kMaxBalls},
    {"ball_joint", 2, kMaxBalls* kBallInfluences},
    {"ball_weight", 4, kMaxBalls* kBallInfluences},
    {"ball_jiggle", 4, kMaxBalls},
    {"pairs", sizeof(BallPair), kMaxPairs},
    {"bulges", sizeof(BulgeRecord), kMaxBalls},
    {"vertex_ball", 2, kMaxVertices* kVertexBalls},
    {"vertex_weight", 4, kMaxVertices* kVertexBalls},
    {"vertex_disp", sizeof(fx::Vec3), kMaxVertices* kVertexBalls},
    {"joint_balls", sizeof(JointBall), kMaxJointBalls},
    {"jv_vertex", 4, kMaxVertices},
    {"jv_ball", 2, kMaxVertices},
    {"jv_alpha", 4, kMaxVertices},
    {"jv_blend", 4, kMaxVertices},
    {"jv_disp", sizeof(fx::Vec3), kMaxVertices},
    {"jv_laplacian", sizeof(fx::Vec3), kMaxVertices},
    {"jv_neighbour_begin", 4, kMaxVertices + 1},
    {"jv_neighbours", 4, kMaxVertices* kMaxNeighbours},
    {"jv_inv_count", 4, kMaxVertices},
    {"overlaps", sizeof(OverlapRecord), kMaxOverlaps},
    {"overlap_vertices", 4, kMaxVertices},
    {"overlap_balls", 2, kMaxOverlapBalls},
    // Version 2 only.
    {"action_lines", sizeof(ActionLine), kMaxActionLines},
    {"action_balls", sizeof(ActionBall), kMaxActionBalls},
};
inline constexpr layer::SectionVersion kMetaballsSectionVersions[] = {
    {layer::kLayerSectionVersion, sizeof(MetaballsSectionParams), kMetaballsArrays},
    {kMetaballsSectionVersion2, sizeof(MetaballsSectionParams), kMetaballsArraysV2},
    {kMetaballsSectionVersion3, sizeof(MetaballsSectionParams), kMetaballsArraysV2},
};
inline constexpr layer::SectionDescriptor kMetaballsSection = {kSectionMetaballs, "MBAL", kMetaballsSectionArrays,
                                                               kMetaballsSectionVersions, 1};

}  // namespace sinew::metaballs
