// A loaded rig: validated, immutable, read by every runtime job. All arrays
// live in a caller-provided arena sized by rig_arena_bytes(); nothing here
// allocates. See rig_format.hpp for units and Q formats of every field.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "rig_format.hpp"
#include "sim_core/fixed/status.hpp"

namespace sinew::rig {

struct Rig {
  int32_t length_exponent = 0;  // one rig unit = 2^length_exponent metres
  uint32_t influences_per_vertex = 0;
  std::span<const JointRecord> joints;
  std::span<const char[kNameBytes]> names;  // empty if the blob has none
  std::span<const SynergyRecord> synergies;
  std::span<const PaletteRecord> palette;
  std::span<const fx::Len> position[3];         // rest positions, SoA
  std::span<const fx::Unit> normal[3];          // rest normals, SoA (empty if none)
  std::span<const uint16_t> influence_palette;  // [vertex * K + k]
  std::span<const fx::Unit> influence_weight;   // [vertex * K + k], sums to 2^30
  std::span<const uint8_t> method;              // SkinMethod per vertex
  std::span<const uint32_t> triangles;          // 3 per triangle
  std::span<const PrimitiveRecord> primitives;
  uint32_t input_count = 0;
  bool any_dual_quaternion = false;
  bool synergy_shares = false;  // major >= 2: SynergyRecord::mode is read

  uint32_t joint_count() const { return static_cast<uint32_t>(joints.size()); }
  uint32_t vertex_count() const { return static_cast<uint32_t>(position[0].size()); }
};

enum class LoadError : uint8_t {
  kNone = 0,
  kTruncated,   // blob shorter than its header or its declared size
  kMisaligned,  // blob pointer not 8-byte aligned
  kBadMagic,
  kBadVersion,
  kBadHeader,     // inconsistent header fields
  kChecksum,      // CRC-32C mismatch
  kSectionTable,  // table out of bounds, misaligned or overlapping entries
  kMissingSection,
  kSectionSize,  // a section's size disagrees with its count
  kLimit,        // a count beyond the documented maxima
  kBadIndex,     // an index out of range (parent, palette, joint, vertex, input)
  kBadValue,     // a value out of its documented range (weights, axes, limits)
  kArenaTooSmall,
};

using LoadStatus = fx::Status<LoadError>;  // the message names the offending section and field

// Checks what a blob's first 64 bytes say (magic, version, header size and
// total_size) against the size of the file holding it, so a loader can
// refuse a file that is not a rig before reading it whole. A file longer
// than the declared total_size is refused too. rig_validate still checks
// everything (this is not a substitute).
LoadStatus rig_check_prefix(const uint8_t* head, size_t head_bytes, uint64_t file_bytes);

// Validates a blob completely and reports the arena bytes rig_init needs.
LoadStatus rig_validate(const uint8_t* blob, size_t size, size_t* arena_bytes);

// Validates, then copies the blob's arrays into `arena` (8-byte aligned,
// at least rig_validate's arena_bytes) and points `out` at them. The blob may
// be released afterwards.
LoadStatus rig_init(const uint8_t* blob, size_t size, void* arena, size_t arena_bytes, Rig* out);

const char* load_error_name(LoadError e);

}  // namespace sinew::rig
