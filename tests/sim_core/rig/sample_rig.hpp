// A small hand-made rig and helpers to patch its compiled blob.
//   joints: root (1 translation DOF), knuckle (2 rotation DOFs), tip (1);
//   a synergy knuckle.0 -> tip.0; 3 palette entries; a 2 x 10 vertex strip
//   with 2 or 3 influences; 18 triangles; one primitive.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "host_tools/rigc/rig_spec.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::test {

rigc::RigSpec sample_rig_spec();

// A blob in 8-byte-aligned storage (the loader requires the alignment).
class Blob {
 public:
  Blob() = default;
  explicit Blob(const std::vector<uint8_t>& bytes);
  uint8_t* data() { return reinterpret_cast<uint8_t*>(words_.data()); }
  const uint8_t* data() const { return reinterpret_cast<const uint8_t*>(words_.data()); }
  size_t size() const { return size_; }

  template <typename T>
  T read(size_t offset) const {
    T value;
    std::memcpy(&value, data() + offset, sizeof(T));
    return value;
  }
  template <typename T>
  void write(size_t offset, const T& value) {
    std::memcpy(data() + offset, &value, sizeof(T));
  }

  rig::FileHeader header() const { return read<rig::FileHeader>(0); }
  void set_header(const rig::FileHeader& h) { write(0, h); }
  // Offset of the section table entry for `id` and of the section's payload.
  size_t entry_offset(uint32_t id) const;
  size_t section_offset(uint32_t id) const { return read<rig::SectionEntry>(entry_offset(id)).offset; }
  // Recomputes the CRC-32C (crc field read as zero) after a patch, so the
  // field checks behind the checksum are reached.
  void reseal();

 private:
  std::vector<uint64_t> words_;
  size_t size_ = 0;
};

// The sample spec compiled (fails the calling test on a compile error).
Blob compile_sample();

struct Section {
  uint32_t id;
  std::vector<uint8_t> bytes;  // unpadded payload
};

// The blob's sections in table order.
std::vector<Section> sections_of(const Blob& blob);

// Lays out header, table and sections as compile_rig does (each padded to 8),
// with section_count, offsets, total_size and the CRC filled in.
Blob assemble(rig::FileHeader header, const std::vector<Section>& sections);

// Joint record of `index` in a blob's JNTS section.
inline size_t joint_offset(const Blob& b, uint32_t index) {
  return b.section_offset(rig::kSectionJoints) + index * sizeof(rig::JointRecord);
}

}  // namespace sinew::test
