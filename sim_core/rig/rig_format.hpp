// Binary rig format v1: the offline/runtime contract (docs/rig-format.md).
//
// Little-endian. The blob starts with a fixed 64-byte header, then a section
// table, then 8-byte-aligned section payloads. A CRC-32C (Castagnoli) over the
// whole blob, computed with the crc field itself read as zero, detects
// corruption; ozz-animation's archives carry no such check, sinew's must.
// Every offset, size, count and index is validated by the loader against the
// blob and against the maxima below before anything is read.
#pragma once

#include <cstdint>

#include "sim_core/fixed/mat34.hpp"

namespace sinew::rig {

inline constexpr uint32_t kMagic = 0x47524E53u;  // "SNRG" read as little-endian u32
// Major 2 adds shared synergies (SynergyMode::kShare). rigc writes major 1
// for every blob without them, so those blobs are unchanged and 1.x loaders
// keep reading them; a 1.x loader refuses a major-2 blob instead of reading
// a shared synergy as an additive one.
inline constexpr uint16_t kVersionMajorFirst = 1;
inline constexpr uint16_t kVersionMajorShares = 2;
inline constexpr uint16_t kVersionMajor = kVersionMajorShares;  // newest major this loader reads
inline constexpr uint16_t kVersionMinor = 0;

// Documented maxima: a blob beyond them is rejected, which also bounds the
// worst-case work of one step.
inline constexpr uint32_t kMaxJoints = 1024;
inline constexpr uint32_t kMaxPalette = 4096;
inline constexpr uint32_t kMaxVertices = 1u << 20;
inline constexpr uint32_t kMaxTriangles = 1u << 21;
inline constexpr uint32_t kMaxInfluences = 8;
inline constexpr uint32_t kMaxInputs = 3 * kMaxJoints;
inline constexpr uint32_t kMaxSynergies = 4 * kMaxJoints;
inline constexpr uint32_t kMaxPrimitives = 1024;
inline constexpr uint32_t kMaxSections = 32;
inline constexpr int32_t kMinLengthExponent = -16;
inline constexpr int32_t kMaxLengthExponent = 16;
inline constexpr uint32_t kNameBytes = 32;

struct FileHeader {        // 64 bytes at offset 0
  uint32_t magic;          // kMagic
  uint16_t version_major;  // 1, or 2 with shared synergies; others are rejected
  uint16_t version_minor;  // newer minors are accepted (additive sections)
  uint32_t header_size;    // sizeof(FileHeader)
  uint32_t total_size;     // bytes in the blob, multiple of 8
  uint32_t crc32c;         // CRC-32C of the blob with this field as zero
  uint32_t section_count;  // entries in the section table
  uint32_t section_table_offset;
  int32_t length_exponent;  // one rig unit = 2^length_exponent metres (or model units)
  uint32_t joint_count;
  uint32_t palette_count;  // skinning bind entries (joint + inverse bind)
  uint32_t vertex_count;
  uint32_t triangle_count;
  uint32_t influences_per_vertex;  // K, 1..kMaxInfluences; every vertex has K slots
  uint32_t input_count;            // commanded degrees of freedom
  uint32_t synergy_count;
  uint32_t primitive_count;
};
static_assert(sizeof(FileHeader) == 64);

enum SectionId : uint32_t {
  kSectionJoints = 0x53544E4Au,            // "JNTS": JointRecord[joint_count]
  kSectionNames = 0x454D414Eu,             // "NAME": char[kNameBytes][joint_count], NUL-terminated
  kSectionSynergies = 0x524E5953u,         // "SYNR": SynergyRecord[synergy_count]
  kSectionPalette = 0x544C4150u,           // "PALT": PaletteRecord[palette_count]
  kSectionPositions = 0x534F5056u,         // "VPOS": Len x[n], y[n], z[n]
  kSectionNormals = 0x4D524E56u,           // "VNRM": Unit x[n], y[n], z[n]
  kSectionInfluenceJoints = 0x4A464E49u,   // "INFJ": uint16 palette index [n*K]
  kSectionInfluenceWeights = 0x57464E49u,  // "INFW": Unit weight [n*K], each vertex sums to 2^30
  kSectionVertexMethod = 0x4854454Du,      // "METH": uint8 SkinMethod [n]
  kSectionTriangles = 0x53495254u,         // "TRIS": uint32 [3*triangle_count]
  kSectionPrimitives = 0x4D495250u,        // "PRIM": PrimitiveRecord[primitive_count]
};

struct SectionEntry {  // 16 bytes
  uint32_t id;
  uint32_t offset;  // from blob start, multiple of 8
  uint32_t size;    // bytes
  uint32_t reserved;
};
static_assert(sizeof(SectionEntry) == 16);

enum class DofKind : uint8_t { kRotation = 0, kTranslation = 1 };
enum class SkinMethod : uint8_t { kLinear = 0, kDualQuaternion = 1 };

struct JointRecord {     // 128 bytes
  int32_t parent;        // -1 for a root; otherwise < own index (parents first)
  uint8_t dof_count;     // 0..3
  uint8_t dof_kind;      // DofKind
  uint16_t first_input;  // index of the first DOF in the input array
  fx::Len rest_translation[3];
  fx::Unit rest_rotation[4];  // w, x, y, z, unit length
  fx::Lin rest_scale[3];
  fx::Unit dof_axis[3][3];  // unit axes in the joint's rest frame
  int32_t dof_min[3];       // binary angle (signed) or Len
  int32_t dof_max[3];
  uint32_t reserved[5];
};
static_assert(sizeof(JointRecord) == 128);

enum class SynergyMode : uint8_t {
  kAdd = 0,    // target DOF += gain * source input; the source keeps all of it
  kShare = 1,  // the same amount also leaves the source's own DOF (a chain,
               // anatomically-based §3: the command is spread, its sum kept)
};

struct SynergyRecord {  // 12 bytes: target DOF += gain * source input
  uint16_t source_input;
  uint16_t target_joint;
  uint8_t target_dof;
  uint8_t mode;  // SynergyMode; read only in major 2 (major 1 wrote 0: kAdd)
  uint8_t reserved[2];
  fx::Unit gain;  // Q2.30; kShare: the target's share of the command, [0, 1]
};
static_assert(sizeof(SynergyRecord) == 12);

struct PaletteRecord {  // 52 bytes: one skinning bind entry
  uint32_t joint;
  fx::Mat34 inverse_bind;  // model space -> joint space at bind time
};
static_assert(sizeof(PaletteRecord) == 52);

struct PrimitiveRecord {  // 8 bytes: a source primitive's vertex range (for exports)
  uint32_t first_vertex;
  uint32_t vertex_count;
};
static_assert(sizeof(PrimitiveRecord) == 8);

}  // namespace sinew::rig
