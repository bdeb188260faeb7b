// Rig blob validation and loading. Every field is checked against the blob
// bounds and the documented maxima before it is used; records are read by
// memcpy (no unaligned or type-punned access).
#include <cstring>

#include "crc32c.hpp"
#include "message.hpp"
#include "rig.hpp"

namespace sinew::rig {
namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the rig format is little-endian; so are all targets");

struct SectionSpan {
  uint32_t offset = 0;
  uint32_t size = 0;
  bool present = false;
};

struct Sections {
  SectionSpan joints, names, synergies, palette, positions, normals, inf_joints, inf_weights, method, triangles,
      primitives;
};

LoadStatus fail(LoadError e, const char* section, const char* field, const char* what, int64_t index = -1,
                int64_t value = 0, bool show_value = false) {
  LoadStatus s;
  s.error = e;
  MessageBuilder m(s.message, sizeof(s.message));
  m.text("rig blob: ").text(section);
  if (index >= 0) m.text("[").number(index).text("]");
  if (field != nullptr && *field != '\0') m.text(".").text(field);
  m.text(": ").text(what);
  if (show_value) m.text(" (").number(value).text(")");
  return s;
}

template <typename T>
T read_at(const uint8_t* blob, uint32_t offset, uint32_t index) {
  T value;
  std::memcpy(&value, blob + offset + static_cast<size_t>(index) * sizeof(T), sizeof(T));
  return value;
}

SectionSpan* slot_for(Sections& s, uint32_t id) {
  switch (id) {
    case kSectionJoints:
      return &s.joints;
    case kSectionNames:
      return &s.names;
    case kSectionSynergies:
      return &s.synergies;
    case kSectionPalette:
      return &s.palette;
    case kSectionPositions:
      return &s.positions;
    case kSectionNormals:
      return &s.normals;
    case kSectionInfluenceJoints:
      return &s.inf_joints;
    case kSectionInfluenceWeights:
      return &s.inf_weights;
    case kSectionVertexMethod:
      return &s.method;
    case kSectionTriangles:
      return &s.triangles;
    case kSectionPrimitives:
      return &s.primitives;
    default:
      return nullptr;  // unknown sections are skipped (newer minor versions)
  }
}

constexpr uint64_t align8(uint64_t v) { return (v + 7u) & ~uint64_t{7}; }

LoadStatus check_size(const SectionSpan& s, const char* name, uint64_t expected, bool required) {
  if (!s.present) {
    if (required && expected > 0) return fail(LoadError::kMissingSection, name, "", "required section is missing");
    return {};
  }
  // Every section is padded with zeros to a multiple of 8 bytes.
  if (s.size != align8(expected))
    return fail(LoadError::kSectionSize, name, "size", "does not match the header counts", -1,
                static_cast<int64_t>(s.size), true);
  return {};
}

// The fields that say what the blob is and how long: checkable from its
// first 64 bytes alone, before the rest is read.
LoadStatus check_identity(const FileHeader* h, uint64_t size) {
  if (h->magic != kMagic) return fail(LoadError::kBadMagic, "header", "magic", "not a sinew rig blob");
  if (h->version_major < kVersionMajorFirst || h->version_major > kVersionMajor)
    return fail(LoadError::kBadVersion, "header", "version_major", "unsupported major version", -1, h->version_major,
                true);
  if (h->header_size != sizeof(FileHeader))
    return fail(LoadError::kBadHeader, "header", "header_size", "must be 64", -1, h->header_size, true);
  if (h->total_size > size)
    return fail(LoadError::kTruncated, "header", "total_size", "blob is shorter than its declared size", -1,
                h->total_size, true);
  if (h->total_size < sizeof(FileHeader) || (h->total_size & 7u) != 0)
    return fail(LoadError::kBadHeader, "header", "total_size", "must be a multiple of 8 and cover the header", -1,
                h->total_size, true);
  return {};
}

LoadStatus check_header(const uint8_t* blob, size_t size, FileHeader* h) {
  if (blob == nullptr || size < sizeof(FileHeader))
    return fail(LoadError::kTruncated, "header", "", "blob shorter than the 64-byte header", -1,
                static_cast<int64_t>(size), true);
  if ((reinterpret_cast<uintptr_t>(blob) & 7u) != 0)
    return fail(LoadError::kMisaligned, "header", "", "blob is not 8-byte aligned in memory");
  std::memcpy(h, blob, sizeof(FileHeader));
  if (LoadStatus st = check_identity(h, size); !st.ok()) return st;
  // CRC-32C over the blob with the crc field read as zero.
  constexpr uint32_t kCrcOffset = offsetof(FileHeader, crc32c);
  const uint8_t zeros[4] = {0, 0, 0, 0};
  uint32_t crc = crc32c(0, blob, kCrcOffset);
  crc = crc32c(crc, zeros, 4);
  crc = crc32c(crc, blob + kCrcOffset + 4, h->total_size - kCrcOffset - 4);
  if (crc != h->crc32c) return fail(LoadError::kChecksum, "header", "crc32c", "checksum mismatch: blob is corrupt");
  if (h->length_exponent < kMinLengthExponent || h->length_exponent > kMaxLengthExponent)
    return fail(LoadError::kBadValue, "header", "length_exponent", "out of range [-16, 16]", -1, h->length_exponent,
                true);
  struct Limit {
    uint32_t value, max;
    const char* name;
  };
  const Limit limits[] = {{h->joint_count, kMaxJoints, "joint_count"},
                          {h->palette_count, kMaxPalette, "palette_count"},
                          {h->vertex_count, kMaxVertices, "vertex_count"},
                          {h->triangle_count, kMaxTriangles, "triangle_count"},
                          {h->influences_per_vertex, kMaxInfluences, "influences_per_vertex"},
                          {h->input_count, kMaxInputs, "input_count"},
                          {h->synergy_count, kMaxSynergies, "synergy_count"},
                          {h->primitive_count, kMaxPrimitives, "primitive_count"},
                          {h->section_count, kMaxSections, "section_count"}};
  for (const Limit& l : limits)
    if (l.value > l.max)
      return fail(LoadError::kLimit, "header", l.name, "exceeds the documented maximum", -1, l.value, true);
  if (h->joint_count == 0) return fail(LoadError::kBadValue, "header", "joint_count", "a rig needs a joint");
  if (h->vertex_count > 0 && (h->influences_per_vertex == 0 || h->palette_count == 0))
    return fail(LoadError::kBadValue, "header", "influences_per_vertex", "a skin needs influences and a palette");
  return {};
}

LoadStatus read_sections(const uint8_t* blob, const FileHeader& h, Sections* s) {
  const uint64_t table_end = uint64_t{h.section_table_offset} + uint64_t{h.section_count} * sizeof(SectionEntry);
  if (h.section_table_offset < sizeof(FileHeader) || (h.section_table_offset & 7u) != 0 || table_end > h.total_size)
    return fail(LoadError::kSectionTable, "section table", "offset", "outside the blob or misaligned", -1,
                h.section_table_offset, true);
  for (uint32_t i = 0; i < h.section_count; ++i) {
    const SectionEntry e = read_at<SectionEntry>(blob, h.section_table_offset, i);
    if ((e.offset & 7u) != 0 || e.offset < table_end || uint64_t{e.offset} + e.size > h.total_size)
      return fail(LoadError::kSectionTable, "section table", "offset", "section outside the payload or misaligned", i,
                  e.offset, true);
    SectionSpan* slot = slot_for(*s, e.id);
    if (slot == nullptr) continue;
    if (slot->present) return fail(LoadError::kSectionTable, "section table", "id", "duplicate section", i);
    // Known sections must not share bytes: each is copied to its own place.
    for (uint32_t k = 0; k < i; ++k) {
      const SectionEntry other = read_at<SectionEntry>(blob, h.section_table_offset, k);
      if (slot_for(*s, other.id) == nullptr || e.size == 0 || other.size == 0) continue;
      if (uint64_t{e.offset} < uint64_t{other.offset} + other.size &&
          uint64_t{other.offset} < uint64_t{e.offset} + e.size)
        return fail(LoadError::kSectionTable, "section table", "offset", "section overlaps another", i, e.offset, true);
    }
    *slot = {e.offset, e.size, true};
  }
  const uint64_t n = h.vertex_count, k = h.influences_per_vertex;
  LoadStatus st;
  if (!(st = check_size(s->joints, "JNTS", uint64_t{h.joint_count} * sizeof(JointRecord), true)).ok()) return st;
  if (!(st = check_size(s->names, "NAME", uint64_t{h.joint_count} * kNameBytes, false)).ok()) return st;
  if (!(st = check_size(s->synergies, "SYNR", uint64_t{h.synergy_count} * sizeof(SynergyRecord), true)).ok()) return st;
  if (!(st = check_size(s->palette, "PALT", uint64_t{h.palette_count} * sizeof(PaletteRecord), true)).ok()) return st;
  if (!(st = check_size(s->positions, "VPOS", n * 3 * 4, true)).ok()) return st;
  if (!(st = check_size(s->normals, "VNRM", n * 3 * 4, false)).ok()) return st;
  if (!(st = check_size(s->inf_joints, "INFJ", n * k * 2, true)).ok()) return st;
  if (!(st = check_size(s->inf_weights, "INFW", n * k * 4, true)).ok()) return st;
  if (!(st = check_size(s->method, "METH", n, true)).ok()) return st;
  if (!(st = check_size(s->triangles, "TRIS", uint64_t{h.triangle_count} * 12, true)).ok()) return st;
  if (!(st = check_size(s->primitives, "PRIM", uint64_t{h.primitive_count} * sizeof(PrimitiveRecord), true)).ok())
    return st;
  return {};
}

// A Q2.30 vector of unit length: |n^2 - 1| <= 2^-20 (generous for rounding,
// strict enough to catch garbage). Components beyond +-1 (+ rounding) are
// rejected first, which also keeps the sum of squares far from overflow.
bool is_unit(const int32_t* c, int count) {
  int64_t n2 = 0;
  for (int i = 0; i < count; ++i) {
    if (c[i] > (1 << 30) + 1024 || c[i] < -(1 << 30) - 1024) return false;
    n2 += int64_t{c[i]} * c[i];
  }
  const int64_t one = int64_t{1} << 60;
  const int64_t d = n2 - one;
  return d <= (one >> 20) && d >= -(one >> 20);
}

LoadStatus check_joints(const uint8_t* blob, const FileHeader& h, const Sections& s) {
  for (uint32_t j = 0; j < h.joint_count; ++j) {
    const JointRecord r = read_at<JointRecord>(blob, s.joints.offset, j);
    if (r.parent < -1 || r.parent >= static_cast<int64_t>(j))
      return fail(LoadError::kBadIndex, "JNTS", "parent", "must be -1 or an earlier joint", j, r.parent, true);
    if (r.dof_count > 3) return fail(LoadError::kBadValue, "JNTS", "dof_count", "must be 0..3", j, r.dof_count, true);
    if (r.dof_kind > static_cast<uint8_t>(DofKind::kTranslation))
      return fail(LoadError::kBadValue, "JNTS", "dof_kind", "unknown kind", j, r.dof_kind, true);
    if (uint32_t{r.first_input} + r.dof_count > h.input_count)
      return fail(LoadError::kBadIndex, "JNTS", "first_input", "DOF inputs beyond input_count", j, r.first_input, true);
    if (!is_unit(r.rest_rotation, 4))
      return fail(LoadError::kBadValue, "JNTS", "rest_rotation", "not a unit quaternion", j);
    for (int d = 0; d < r.dof_count; ++d) {
      if (!is_unit(r.dof_axis[d], 3)) return fail(LoadError::kBadValue, "JNTS", "dof_axis", "not a unit vector", j);
      if (r.dof_min[d] > r.dof_max[d])
        return fail(LoadError::kBadValue, "JNTS", "dof_min", "greater than dof_max", j, r.dof_min[d], true);
    }
    if (s.names.present) {
      const uint8_t* name = blob + s.names.offset + size_t{j} * kNameBytes;
      if (std::memchr(name, 0, kNameBytes) == nullptr)
        return fail(LoadError::kBadValue, "NAME", "name", "not NUL-terminated within 32 bytes", j);
    }
  }
  for (uint32_t i = 0; i < h.synergy_count; ++i) {
    const SynergyRecord r = read_at<SynergyRecord>(blob, s.synergies.offset, i);
    if (r.source_input >= h.input_count)
      return fail(LoadError::kBadIndex, "SYNR", "source_input", "beyond input_count", i, r.source_input, true);
    if (r.target_joint >= h.joint_count)
      return fail(LoadError::kBadIndex, "SYNR", "target_joint", "beyond joint_count", i, r.target_joint, true);
    const JointRecord t = read_at<JointRecord>(blob, s.joints.offset, r.target_joint);
    if (r.target_dof >= t.dof_count)
      return fail(LoadError::kBadIndex, "SYNR", "target_dof", "beyond the target joint's DOFs", i, r.target_dof, true);
    if (h.version_major >= kVersionMajorShares) {
      if (r.mode > static_cast<uint8_t>(SynergyMode::kShare))
        return fail(LoadError::kBadValue, "SYNR", "mode", "not add (0) or share (1)", i, r.mode, true);
      // A share is a fraction of the command: within [0, 1] the chain's
      // values stay within the command's range.
      if (r.mode == static_cast<uint8_t>(SynergyMode::kShare) && (r.gain < 0 || r.gain > (1 << 30)))
        return fail(LoadError::kBadValue, "SYNR", "gain", "share outside [0, 1]", i, r.gain, true);
    }
  }
  for (uint32_t i = 0; i < h.palette_count; ++i) {
    const PaletteRecord p = read_at<PaletteRecord>(blob, s.palette.offset, i);
    if (p.joint >= h.joint_count)
      return fail(LoadError::kBadIndex, "PALT", "joint", "beyond joint_count", i, p.joint, true);
    for (const auto& row : p.inverse_bind.m)
      for (const fx::Lin e : row)
        if (e > (1 << 30) || e < -(1 << 30))
          return fail(LoadError::kBadValue, "PALT", "inverse_bind", "linear entry beyond +-64", i, e, true);
  }
  return {};
}

LoadStatus check_skin(const uint8_t* blob, const FileHeader& h, const Sections& s) {
  const uint32_t k = h.influences_per_vertex;
  for (uint32_t v = 0; v < h.vertex_count; ++v) {
    int64_t sum = 0;
    for (uint32_t i = 0; i < k; ++i) {
      const uint16_t p = read_at<uint16_t>(blob, s.inf_joints.offset, v * k + i);
      const fx::Unit w = read_at<fx::Unit>(blob, s.inf_weights.offset, v * k + i);
      if (p >= h.palette_count)
        return fail(LoadError::kBadIndex, "INFJ", "palette_index", "beyond palette_count", v, p, true);
      if (w < 0 || w > fx::kUnitOne) return fail(LoadError::kBadValue, "INFW", "weight", "outside [0, 1]", v, w, true);
      sum += w;
    }
    if (sum != fx::kUnitOne)
      return fail(LoadError::kBadValue, "INFW", "weight", "weights do not sum to exactly 2^30", v, sum, true);
    const uint8_t m = read_at<uint8_t>(blob, s.method.offset, v);
    if (m > static_cast<uint8_t>(SkinMethod::kDualQuaternion))
      return fail(LoadError::kBadValue, "METH", "method", "unknown skinning method", v, m, true);
  }
  for (uint32_t t = 0; t < h.triangle_count * 3; ++t) {
    const uint32_t index = read_at<uint32_t>(blob, s.triangles.offset, t);
    if (index >= h.vertex_count)
      return fail(LoadError::kBadIndex, "TRIS", "vertex", "beyond vertex_count", t / 3, index, true);
  }
  for (uint32_t i = 0; i < h.primitive_count; ++i) {
    const PrimitiveRecord p = read_at<PrimitiveRecord>(blob, s.primitives.offset, i);
    if (uint64_t{p.first_vertex} + p.vertex_count > h.vertex_count)
      return fail(LoadError::kBadIndex, "PRIM", "vertex_count", "range beyond vertex_count", i, p.first_vertex, true);
  }
  return {};
}

LoadStatus validate(const uint8_t* blob, size_t size, FileHeader* h, Sections* s, size_t* arena_bytes) {
  LoadStatus st = check_header(blob, size, h);
  if (!st.ok()) return st;
  if (!(st = read_sections(blob, *h, s)).ok()) return st;
  if (!(st = check_joints(blob, *h, *s)).ok()) return st;
  if (!(st = check_skin(blob, *h, *s)).ok()) return st;
  const SectionSpan* all[] = {&s->joints,     &s->names,       &s->synergies, &s->palette,   &s->positions, &s->normals,
                              &s->inf_joints, &s->inf_weights, &s->method,    &s->triangles, &s->primitives};
  size_t bytes = 0;
  for (const SectionSpan* p : all)
    if (p->present) bytes += static_cast<size_t>(align8(p->size));  // <= total_size: fits
  *arena_bytes = bytes;
  return {};
}

// Copies one section into the arena and returns where it went.
const uint8_t* place(const uint8_t* blob, const SectionSpan& s, uint8_t* arena, size_t* used) {
  if (!s.present || s.size == 0) return nullptr;
  uint8_t* dst = arena + *used;
  std::memcpy(dst, blob + s.offset, s.size);
  *used += static_cast<size_t>(align8(s.size));
  return dst;
}

template <typename T>
std::span<const T> typed(const uint8_t* p, size_t count) {
  if (p == nullptr || count == 0) return {};
  static_assert(alignof(T) <= 8, "sections are 8-byte aligned in the arena");
  // The arena bytes were written by memcpy, which creates implicit objects.
  return {static_cast<const T*>(static_cast<const void*>(p)), count};
}

}  // namespace

LoadStatus rig_check_prefix(const uint8_t* head, size_t head_bytes, uint64_t file_bytes) {
  if (head == nullptr || head_bytes < sizeof(FileHeader) || file_bytes < sizeof(FileHeader))
    return fail(LoadError::kTruncated, "header", "", "blob shorter than the 64-byte header", -1,
                static_cast<int64_t>(file_bytes < head_bytes ? file_bytes : head_bytes), true);
  FileHeader h;
  std::memcpy(&h, head, sizeof(FileHeader));
  if (LoadStatus st = check_identity(&h, file_bytes); !st.ok()) return st;
  // rigc writes exactly total_size bytes; more is not a blob it wrote.
  if (h.total_size != file_bytes)
    return fail(LoadError::kBadHeader, "header", "total_size", "the file is longer than the blob it declares", -1,
                h.total_size, true);
  return {};
}

LoadStatus rig_validate(const uint8_t* blob, size_t size, size_t* arena_bytes) {
  FileHeader h;
  Sections s;
  return validate(blob, size, &h, &s, arena_bytes);
}

LoadStatus rig_init(const uint8_t* blob, size_t size, void* arena, size_t arena_bytes, Rig* out) {
  FileHeader h;
  Sections s;
  size_t needed = 0;
  LoadStatus st = validate(blob, size, &h, &s, &needed);
  if (!st.ok()) return st;
  if (arena == nullptr || arena_bytes < needed || (reinterpret_cast<uintptr_t>(arena) & 7u) != 0)
    return fail(LoadError::kArenaTooSmall, "arena", "", "smaller than rig_validate's arena_bytes or misaligned", -1,
                static_cast<int64_t>(needed), true);
  uint8_t* a = static_cast<uint8_t*>(arena);
  size_t used = 0;
  const size_t n = h.vertex_count, nk = size_t{h.vertex_count} * h.influences_per_vertex;
  Rig r;
  r.length_exponent = h.length_exponent;
  r.influences_per_vertex = h.influences_per_vertex;
  r.input_count = h.input_count;
  r.synergy_shares = h.version_major >= kVersionMajorShares;
  r.joints = typed<JointRecord>(place(blob, s.joints, a, &used), h.joint_count);
  r.names = typed<char[kNameBytes]>(place(blob, s.names, a, &used), h.joint_count);
  r.synergies = typed<SynergyRecord>(place(blob, s.synergies, a, &used), h.synergy_count);
  r.palette = typed<PaletteRecord>(place(blob, s.palette, a, &used), h.palette_count);
  const uint8_t* pos = place(blob, s.positions, a, &used);
  const uint8_t* nrm = place(blob, s.normals, a, &used);
  for (size_t c = 0; c < 3; ++c) {
    r.position[c] = typed<fx::Len>(pos == nullptr ? nullptr : pos + c * n * 4, n);
    r.normal[c] = typed<fx::Unit>(nrm == nullptr ? nullptr : nrm + c * n * 4, n);
  }
  r.influence_palette = typed<uint16_t>(place(blob, s.inf_joints, a, &used), nk);
  r.influence_weight = typed<fx::Unit>(place(blob, s.inf_weights, a, &used), nk);
  r.method = typed<uint8_t>(place(blob, s.method, a, &used), n);
  r.triangles = typed<uint32_t>(place(blob, s.triangles, a, &used), size_t{h.triangle_count} * 3);
  r.primitives = typed<PrimitiveRecord>(place(blob, s.primitives, a, &used), h.primitive_count);
  for (const uint8_t m : r.method) r.any_dual_quaternion |= m == static_cast<uint8_t>(SkinMethod::kDualQuaternion);
  *out = r;
  return {};
}

const char* load_error_name(LoadError e) {
  switch (e) {
    case LoadError::kNone:
      return "none";
    case LoadError::kTruncated:
      return "truncated";
    case LoadError::kMisaligned:
      return "misaligned";
    case LoadError::kBadMagic:
      return "bad-magic";
    case LoadError::kBadVersion:
      return "bad-version";
    case LoadError::kBadHeader:
      return "bad-header";
    case LoadError::kChecksum:
      return "checksum";
    case LoadError::kSectionTable:
      return "section-table";
    case LoadError::kMissingSection:
      return "missing-section";
    case LoadError::kSectionSize:
      return "section-size";
    case LoadError::kLimit:
      return "limit";
    case LoadError::kBadIndex:
      return "bad-index";
    case LoadError::kBadValue:
      return "bad-value";
    case LoadError::kArenaTooSmall:
      return "arena-too-small";
  }
  return "unknown";
}

}  // namespace sinew::rig
