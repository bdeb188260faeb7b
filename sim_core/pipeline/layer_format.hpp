// Layer sections of the binary rig format, version 1.1 (docs/rig-format.md,
// "Layer sections"): the physical layers a rig compiler built offline, in
// fixed point, so the board only loads and validates them.
//
// A 1.0 loader skips these sections (unknown ids). Every layer section has
// the same shape, so one reader bounds-checks all of them:
//
//   LayerSectionHeader   32 bytes
//   params               params_size bytes, the layer's fixed record below,
//                        padded with zeros to a multiple of 8
//   LayerArrayEntry[n]   16 bytes each: where each of the layer's arrays is
//   arrays               each at a multiple of 8 from the section start
//
// Records are the runtime models' own plain structs (little-endian, int32
// based, no pointers, no implicit padding: every byte is a zero-initialised
// member, so a blob's bytes are the same from every compiler); their sizes
// are pinned by static_asserts here so a layout change cannot go unnoticed.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sim_core/barnet/barnet_model.hpp"
#include "sim_core/elastic_skin/skin_model.hpp"
#include "sim_core/metaballs/model.hpp"
#include "sim_core/muscle/muscle_model.hpp"
#include "sim_core/rig/rig_format.hpp"
#include "sim_core/sph/sph_model.hpp"

namespace sinew::pipeline {

enum LayerSectionId : uint32_t {
  kSectionSphJoint = 0x4A485053u,        // "SPHJ": one SPH elastic joint; may repeat
  kSectionMetaballs = 0x4C41424Du,       // "MBAL": the metaballs skin; at most one
  kSectionMuscles = 0x4353554Du,         // "MUSC": every muscle and primitive; at most one
  kSectionElasticSkin = 0x4E494B53u,     // "SKIN": the elastic skin; needs MUSC; at most one
  kSectionBarnet = 0x54454E42u,          // "BNET": one bar-net; may repeat
  kSectionExternalInputs = 0x49545845u,  // "EXTI": ExternalInputRecord[]; at most one
};

inline constexpr uint32_t kLayerSectionVersion = 1;
inline constexpr uint32_t kMaxSphJoints = 8;
inline constexpr uint32_t kMaxBarnets = 8;
inline constexpr uint32_t kMaxExternalInputs = 64;
inline constexpr uint32_t kMaxLayerArrays = 32;
inline constexpr uint32_t kUnitBytes = 16;

struct LayerSectionHeader {  // 32 bytes at the start of every layer section
  uint32_t layer_version;    // kLayerSectionVersion
  uint32_t params_size;      // bytes of the params record (unpadded); must equal the loader's
  uint32_t array_count;      // entries of the array table; must equal the layer's
  uint32_t rate_hz;          // tick rate the gains were built for; 0 when they do not depend on it
  uint32_t reserved[4];      // 0 written; not checked
};
static_assert(sizeof(LayerSectionHeader) == 32);

struct LayerArrayEntry {  // 16 bytes
  uint32_t offset;        // from the section start, a multiple of 8
  uint32_t count;         // elements
  uint32_t element_size;  // bytes per element; must equal the loader's
  uint32_t reserved;
};
static_assert(sizeof(LayerArrayEntry) == 16);

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

// SPHJ params. Arrays, in order: rest_local x, y, z (Len), rest_model x, y, z
// (Len), bone (u8), skin_vertex (u32), skin_rest x, y, z (Len).
//
// Layer version 1: SphSectionParamsV1, the SphParams fields before
// tension_gain; it loads with tension_gain = 0 (no surface tension). Layer
// version 2 (SPHJ only): SphSectionParams, the whole SphParams. Both records
// are 84 bytes. Writers emit version 1 whenever tension_gain is 0, so rigs
// without surface tension keep their bytes; a loader that knows only version
// 1 refuses a version 2 section (kBadVersion).
inline constexpr uint32_t kSphParamsV1Bytes = 44;  // SphParams up to grid_radius
struct SphSectionParamsV1 {
  uint8_t params[kSphParamsV1Bytes];  // the first 44 bytes of sph::SphParams
  sph::SphJoint joint;
  uint32_t force_input;  // index into EXTI of the force at the load point, or kNoExternalInput
  uint32_t reserved;
};
struct SphSectionParams {
  sph::SphParams params;
  sph::SphJoint joint;
  uint32_t force_input;  // as in version 1
};
static_assert(sizeof(sph::SphParams) == 48 && offsetof(sph::SphParams, tension_gain) == kSphParamsV1Bytes &&
              sizeof(sph::SphJoint) == 32);
static_assert(sizeof(SphSectionParamsV1) == 84 && sizeof(SphSectionParams) == 84);
inline constexpr uint32_t kSphSectionVersion2 = 2;
inline constexpr uint32_t kSphArrays = 11;

// MBAL params. Arrays, in order: inverse_bind, ball_rest, ball_radius,
// ball_bone, ball_joint, ball_weight, ball_jiggle, pairs, bulges,
// vertex_ball, vertex_weight, vertex_disp, joint_balls, jv_vertex, jv_ball,
// jv_alpha, jv_blend, jv_disp, jv_laplacian, jv_neighbour_begin,
// jv_neighbours, jv_inv_count, overlaps, overlap_vertices, overlap_balls.
// The header's rate_hz is the model's jiggle_rate_hz (0: per-step gains).
//
// Layer version 1: those 25 arrays, no action lines. Layer version 2 (MBAL
// only) appends two: action_lines (metaballs::ActionLine) and action_balls
// (metaballs::ActionBall). Writers emit version 1 whenever the model has no
// action line, so rigs without them keep their bytes; a loader that knows
// only version 1 refuses a version 2 section (kBadVersion).
struct MetaballsSectionParams {
  uint32_t joint_count, vertex_count;
  uint32_t pbd_iterations;
  fx::Unit jiggle_damping;
  uint32_t smoothing_passes;
  fx::Unit smoothing_rate;
};
static_assert(sizeof(metaballs::BallPair) == 20 && sizeof(metaballs::BulgeRecord) == 12 &&
              sizeof(metaballs::JointBall) == 24 && sizeof(metaballs::OverlapRecord) == 64);
inline constexpr uint32_t kMetaballsArrays = 25;
inline constexpr uint32_t kMetaballsSectionVersion2 = 2;
inline constexpr uint32_t kMetaballsArraysV2 = 27;
static_assert(sizeof(metaballs::ActionLine) == 32 && sizeof(metaballs::ActionBall) == 16);

// MUSC params. Arrays: muscles (MuscleRecord), primitives (PrimitiveRecord).
// Layer version 2 (MUSC only) appends a third array, deformations
// (PrimitiveDeformation, empty or one per primitive: Barr's taper, twist and
// bend). Writers emit version 1 while no primitive is deformed, so rigs
// without deformations keep their bytes; a version-1-only loader refuses a
// version 2 MUSC section (kBadVersion).
// Layer version 3 appends a fourth array, shapes (MuscleShape, empty or one
// per muscle: §4.2 end axes from bone normals, Table 1 slice edits and the
// variable pivot); the deformations array is then present and may be
// empty. Writers emit version 3 only when a muscle has a non-default shape;
// versions 1 and 2 still load (every muscle then has the default shape).
// Layer version 4 appends a fifth array, exponents (PrimitiveExponents,
// empty or one per primitive: Barr's two superquadric exponents, Q16.16 in
// [1, 16]); deformations and shapes are then present and may be empty.
// Writers emit version 4 only when some primitive's exponents are not an
// equal 2, 4 or 8 (its record's exponent is then 0); versions 1 to 3 load
// with every primitive's exponent its record's.
struct MusclesSectionParams {
  uint32_t joint_count, ring_vertices;
};
static_assert(sizeof(muscle::MuscleRecord) == 184 && sizeof(muscle::PrimitiveRecord) == 36 &&
              sizeof(muscle::PrimitiveDeformation) == 16 && sizeof(muscle::MuscleShape) == 440 &&
              sizeof(muscle::PrimitiveExponents) == 8);
inline constexpr uint32_t kMusclesArrays = 2;
inline constexpr uint32_t kMusclesSectionVersion2 = 2;
inline constexpr uint32_t kMusclesArraysV2 = 3;
inline constexpr uint32_t kMusclesSectionVersion3 = 3;
inline constexpr uint32_t kMusclesArraysV3 = 4;
inline constexpr uint32_t kMusclesSectionVersion4 = 4;
inline constexpr uint32_t kMusclesArraysV4 = 5;

// SKIN params. Arrays: anchors, anchor_stiffness, fat, edges, bands, then
// the skin's support region: region_vertex (u32, ascending) and
// region_weight (Unit, (0, 1]): the relaxed skin displaces those vertices by
// weight x (relaxed - skinned); every other vertex keeps its skinned
// position bit for bit. Both empty: the whole skin, weight 1.
//
// Layer version 1 (every section): the params are SkinSectionParams and the
// solver is elastic_skin::SkinSolverParams{} (static relaxation, no
// tolerance, no global fat). Layer version 2 (SKIN only) appends the solver
// record: SkinSectionParamsV2 (dynamic mode, tolerance, global fat). Writers
// emit version 1 whenever the solver record is the default, so rigs without
// the new settings keep their bytes; a loader that knows only version 1
// refuses a version 2 SKIN section (kBadVersion) instead of misreading it.
// Layer version 3 (SKIN only) carries the whole solver record, whose last
// member, edge_damping, version 2 lacks (its 52 bytes are the record's
// first 52; edge_damping then reads 0). Writers emit version 3 only when
// edge_damping is not 0. Layer version 4 (SKIN only): the version 3 record
// whose solver.fat_normal (the byte after mode, reserved before) may be
// FatNormal::kSurface; writers emit it only then, and a loader reads that
// byte as 0 (the anchor normal) in every older version. The skin's faces
// are the rig's triangles (SkinModel::triangles), not stored again.
// Layer version 5 (SKIN only): the version 3 record (fat_normal as in
// version 4) followed by the three external inputs (EXTI indices, or
// kNoExternalInput) that measure the acceleration of the frame the bones
// are given in, x, y, z in the rig's axes (InputQuantity::kAcceleration):
// the dynamic skin feels -a_base (LEMAN §3). Writers emit it only when one
// is set.
struct SkinSectionParams {
  uint32_t joint_count, vertex_count;
  elastic_skin::SkinParams params;
};
inline constexpr uint32_t kSkinSolverBytesV2 = 52;
struct SkinSectionParamsV2 {
  uint32_t joint_count, vertex_count;
  elastic_skin::SkinParams params;
  uint8_t solver[kSkinSolverBytesV2];  // the first 52 bytes of elastic_skin::SkinSolverParams
};
struct SkinSectionParamsV3 {
  uint32_t joint_count, vertex_count;
  elastic_skin::SkinParams params;
  elastic_skin::SkinSolverParams solver;
};
struct SkinSectionParamsV5 {
  SkinSectionParamsV3 v3;
  uint32_t base_acceleration_input[3];
  uint32_t reserved;
};
inline constexpr uint32_t kSkinSectionVersion2 = 2;
inline constexpr uint32_t kSkinSectionVersion3 = 3;
inline constexpr uint32_t kSkinSectionVersion4 = 4;
inline constexpr uint32_t kSkinSectionVersion5 = 5;
static_assert(sizeof(elastic_skin::SkinParams) == 28 && sizeof(elastic_skin::Anchor) == 80 &&
              sizeof(elastic_skin::Edge) == 16 && sizeof(elastic_skin::RubberBand) == 20 &&
              sizeof(elastic_skin::SkinSolverParams) == 56 && sizeof(SkinSectionParamsV2) == 88 &&
              sizeof(SkinSectionParamsV3) == 92 && sizeof(SkinSectionParamsV5) == 108 &&
              offsetof(elastic_skin::SkinSolverParams, edge_damping) == kSkinSolverBytesV2);
inline constexpr uint32_t kSkinArrays = 7;

// BNET params. Arrays: inverse_bind, nodes, bars, loads, triangles, wrap.
// Layer version 1: loads read joint angles only, q is constant; the last
// params word is 0 written, not checked. Layer version 2 (BNET) adds the
// inputs: the last params word is the count of external inputs (EXTI) the
// net was built against, loads may read them (LoadRecord::input from
// input_count on), and a 7th array, q_inputs (ForceDensityInput), scales runs
// of bars' q from them. Writers emit version 1 for a net with neither, so
// those rigs keep their bytes; a version-1-only loader refuses version 2.
struct BarnetSectionParams {
  uint32_t joint_count, input_count, vertex_count;
  uint32_t external_count;  // version 2; version 1: reserved, 0
};
inline constexpr uint32_t kBarnetSectionVersion2 = 2;
static_assert(sizeof(barnet::ForceDensityInput) == 16);
inline constexpr uint32_t kBarnetArraysV2 = 7;
static_assert(sizeof(barnet::NodeRecord) == 40 && sizeof(barnet::BarRecord) == 12 && sizeof(barnet::LoadRecord) == 28 &&
              sizeof(barnet::ControlTriangle) == 12 && sizeof(barnet::WrapRecord) == 24);
inline constexpr uint32_t kBarnetArrays = 6;

// EXTI params: none (params_size 0). Array: ExternalInputRecord[].
inline constexpr uint32_t kExternalInputArrays = 1;

}  // namespace sinew::pipeline
