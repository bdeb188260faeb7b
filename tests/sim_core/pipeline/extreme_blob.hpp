// Edits of a compiled rig blob that push fields the loaders accept to their
// documented limits: the core sections' unchecked transforms
// (docs/rig-format.md, "Not checked") and the layer sections' records
// (sim_core/pipeline/layer_format.hpp). Every edit keeps the blob loadable;
// callers fix the CRC once after their edits.
#pragma once

#include <climits>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <vector>

#include "sim_core/pipeline/layer_format.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::test {

inline size_t core_section(const std::vector<uint8_t>& bytes, uint32_t id) {
  rig::FileHeader h;
  std::memcpy(&h, bytes.data(), sizeof(h));
  for (uint32_t i = 0; i < h.section_count; ++i) {
    rig::SectionEntry e;
    std::memcpy(&e, bytes.data() + h.section_table_offset + i * sizeof(e), sizeof(e));
    if (e.id == id) return e.offset;
  }
  return 0;
}

inline void put_i32(std::vector<uint8_t>* b, size_t at, int32_t v) { std::memcpy(b->data() + at, &v, 4); }
inline int32_t get_i32(const std::vector<uint8_t>& b, size_t at) {
  int32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

// +-max, by a pattern over (record, component), so neighbouring records and
// axes take opposite extremes.
inline int32_t extreme(size_t record, size_t component) {
  return ((record + component) % 2 == 0) ? INT32_MAX : INT32_MIN;
}

// Every joint's rest translation at +-(2^31 - 1) and rest scale at the Lin
// extremes (+-128), every inverse bind's linear entries at +-64 (the
// loader's limit) and its translation at +-(2^31 - 1).
inline void push_core_transforms(std::vector<uint8_t>* bytes, const rig::Rig& rig) {
  const size_t joints = core_section(*bytes, rig::kSectionJoints);
  const size_t palette = core_section(*bytes, rig::kSectionPalette);
  for (uint32_t j = 0; j < rig.joint_count(); ++j) {
    const size_t r = joints + j * sizeof(rig::JointRecord);
    for (size_t c = 0; c < 3; ++c) {
      put_i32(bytes, r + offsetof(rig::JointRecord, rest_translation) + 4 * c, c == 1 ? INT32_MIN : INT32_MAX);
      put_i32(bytes, r + offsetof(rig::JointRecord, rest_scale) + 4 * c, c == 2 ? INT32_MIN : INT32_MAX);
    }
  }
  for (size_t p = 0; p < rig.palette.size(); ++p) {
    const size_t r = palette + p * sizeof(rig::PaletteRecord) + offsetof(rig::PaletteRecord, inverse_bind);
    for (size_t k = 0; k < 9; ++k) put_i32(bytes, r + 4 * k, (k % 2 == 0) ? (1 << 30) : -(1 << 30));
    for (size_t k = 9; k < 12; ++k) put_i32(bytes, r + 4 * k, k == 10 ? INT32_MIN : INT32_MAX);
  }
}

// A rest scale of `lin` (Q8.24) on every joint and axis, e.g. 2.5: large
// but far from the Lin limit.
inline void scale_rest(std::vector<uint8_t>* bytes, const rig::Rig& rig, int32_t lin) {
  const size_t joints = core_section(*bytes, rig::kSectionJoints);
  for (uint32_t j = 0; j < rig.joint_count(); ++j)
    for (size_t c = 0; c < 3; ++c)
      put_i32(bytes, joints + j * sizeof(rig::JointRecord) + offsetof(rig::JointRecord, rest_scale) + 4 * c, lin);
}

// A layer section of a blob: where its params and each array are.
struct LayerView {
  size_t section = 0;  // blob offset of the section; 0 when absent
  size_t params = 0;   // blob offset of its params record
  std::vector<pipeline::LayerArrayEntry> arrays;

  explicit operator bool() const { return section != 0; }
  size_t at(uint32_t array, size_t element) const {
    return section + arrays[array].offset + element * arrays[array].element_size;
  }
  uint32_t count(uint32_t array) const { return arrays[array].count; }
};

inline LayerView layer_view(const std::vector<uint8_t>& bytes, uint32_t id, uint32_t instance = 0) {
  LayerView v;
  rig::FileHeader h;
  std::memcpy(&h, bytes.data(), sizeof(h));
  for (uint32_t i = 0; i < h.section_count; ++i) {
    rig::SectionEntry e;
    std::memcpy(&e, bytes.data() + h.section_table_offset + i * sizeof(e), sizeof(e));
    if (e.id != id || instance-- != 0) continue;
    pipeline::LayerSectionHeader lh;
    std::memcpy(&lh, bytes.data() + e.offset, sizeof(lh));
    v.section = e.offset;
    v.params = e.offset + sizeof(lh);
    const size_t table = v.params + ((lh.params_size + 7u) & ~size_t{7});
    v.arrays.resize(lh.array_count);
    for (uint32_t a = 0; a < lh.array_count; ++a)
      std::memcpy(&v.arrays[a], bytes.data() + table + a * sizeof(pipeline::LayerArrayEntry),
                  sizeof(pipeline::LayerArrayEntry));
    return v;
  }
  return v;
}

// Reads a record of type T at `at`, lets `edit` change it, writes it back.
template <typename T>
void edit_record(std::vector<uint8_t>* bytes, size_t at, const std::function<void(T&, size_t)>& edit, size_t index) {
  T r;
  std::memcpy(&r, bytes->data() + at, sizeof(T));
  edit(r, index);
  std::memcpy(bytes->data() + at, &r, sizeof(T));
}

template <typename T>
void edit_array(std::vector<uint8_t>* bytes, const LayerView& v, uint32_t array,
                const std::function<void(T&, size_t)>& edit) {
  for (size_t i = 0; i < v.count(array); ++i) edit_record<T>(bytes, v.at(array, i), edit, i);
}

}  // namespace sinew::test
