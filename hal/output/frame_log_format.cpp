#include "frame_log_format.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "checksum.hpp"
#include "frame_compression.hpp"
#include "le_bytes.hpp"
#include "pose_codec.hpp"

namespace sinew::hal::output {

namespace {
constexpr size_t kHeaderChecksumAt = 32;
}

void encode_log_header(const FrameShape& shape, bool compressed, uint8_t out[kLogHeaderBytes]) {
  std::memcpy(out, kLogMagic, sizeof(kLogMagic));
  store_u16(out + 8, kLogVersion);
  store_u16(out + 10, static_cast<uint16_t>(kLogHeaderBytes));
  store_u32(out + 12, (shape.normals ? kLogFlagNormals : 0u) | (compressed ? kLogFlagCompressed : 0u));
  store_u32(out + 16, shape.vertex_count);
  store_u32(out + 20, shape.input_count);
  store_i32(out + 24, shape.length_exponent);
  store_u32(out + 28, 0);
  store_u64(out + kHeaderChecksumAt, xxh64({out, kHeaderChecksumAt}));
}

bool parse_log_header(std::span<const uint8_t> bytes, FrameShape* shape, std::string* why, uint32_t* metadata_bytes,
                      bool* compressed) {
  if (bytes.size() < kLogHeaderBytes) return *why = "shorter than a frame log header", false;
  const uint8_t* p = bytes.data();
  if (std::memcmp(p, kLogMagic, sizeof(kLogMagic)) != 0) return *why = "not a frame log (bad magic)", false;
  const uint16_t version = load_u16(p + 8);
  if (version != kLogVersion && version != kLogVersionMetadata)
    return *why = "frame log version " + std::to_string(version) + " (this build reads versions " +
                  std::to_string(kLogVersion) + " and " + std::to_string(kLogVersionMetadata) + ")",
           false;
  if (load_u64(p + kHeaderChecksumAt) != xxh64({p, kHeaderChecksumAt}))
    return *why = "frame log header checksum mismatch", false;
  const uint32_t flags = load_u32(p + 12);
  // Offset 28: reserved (0) in version 1, the metadata's length in version 2.
  const uint32_t metadata = load_u32(p + 28);
  const bool metadata_ok = version == kLogVersion ? metadata == 0 : metadata > 0 && metadata <= kMaxLogMetadataBytes;
  if (load_u16(p + 10) != kLogHeaderBytes || (flags & ~(kLogFlagNormals | kLogFlagCompressed)) != 0 || !metadata_ok)
    return *why = "frame log header has unknown fields", false;
  if (metadata_bytes != nullptr) *metadata_bytes = metadata;
  if (compressed != nullptr) *compressed = (flags & kLogFlagCompressed) != 0;
  shape->normals = (flags & kLogFlagNormals) != 0;
  shape->vertex_count = load_u32(p + 16);
  shape->input_count = load_u32(p + 20);
  shape->length_exponent = load_i32(p + 24);
  if (max_pose_payload_bytes(*shape) == 0) return *why = "frame log header counts are out of range", false;
  return true;
}

std::vector<uint8_t> encode_log_preamble(const FrameShape& shape, std::string_view metadata, bool compressed) {
  std::vector<uint8_t> out(kLogHeaderBytes + (metadata.empty() ? 0 : metadata.size() + 8));
  encode_log_header(shape, compressed, out.data());
  if (!metadata.empty()) {
    store_u16(out.data() + 8, kLogVersionMetadata);
    store_u32(out.data() + 28, static_cast<uint32_t>(metadata.size()));
    store_u64(out.data() + kHeaderChecksumAt, xxh64({out.data(), kHeaderChecksumAt}));
    std::memcpy(out.data() + kLogHeaderBytes, metadata.data(), metadata.size());
    const std::span<const uint8_t> block(out.data() + kLogHeaderBytes, metadata.size());
    store_u64(out.data() + kLogHeaderBytes + metadata.size(), xxh64(block));
  }
  return out;
}

bool read_log_preamble(int fd, uint64_t file_size, LogPreamble* out, std::string* why) {
  uint8_t header[kLogHeaderBytes];
  if (file_size < kLogHeaderBytes) return *why = "shorter than a frame log header", false;
  if (::pread(fd, header, sizeof(header), 0) != static_cast<ssize_t>(sizeof(header)))
    return *why = std::string("cannot read the header: ") + std::strerror(errno), false;
  LogPreamble p;
  uint32_t metadata_bytes = 0;
  if (!parse_log_header(header, &p.shape, why, &metadata_bytes, &p.compressed)) return false;
  if (metadata_bytes > 0) {
    p.records_offset = kLogHeaderBytes + uint64_t{metadata_bytes} + 8;
    if (file_size < p.records_offset) return *why = "metadata block cut short", false;
    std::vector<uint8_t> block(metadata_bytes + 8);
    if (::pread(fd, block.data(), block.size(), kLogHeaderBytes) != static_cast<ssize_t>(block.size()))
      return *why = std::string("cannot read the metadata: ") + std::strerror(errno), false;
    if (load_u64(block.data() + metadata_bytes) != xxh64({block.data(), metadata_bytes}))
      return *why = "metadata checksum mismatch", false;
    p.metadata.assign(reinterpret_cast<const char*>(block.data()), metadata_bytes);
  }
  *out = std::move(p);
  return true;
}

std::string describe_shape_mismatch(const FrameShape& log, const FrameShape& wanted) {
  std::string s;
  auto add = [&s](const char* what, int64_t in_log, int64_t in_rig) {
    if (in_log == in_rig) return;
    if (!s.empty()) s += ", ";
    s += std::string(what) + " " + std::to_string(in_log) + " in the log, " + std::to_string(in_rig) + " now";
  };
  add("vertex count", log.vertex_count, wanted.vertex_count);
  add("input count", log.input_count, wanted.input_count);
  add("length exponent", log.length_exponent, wanted.length_exponent);
  add("normals", log.normals, wanted.normals);
  return s;
}

uint64_t record_checksum(const uint8_t length_field[4], std::span<const uint8_t> payload) {
  return xxh64_concat({length_field, 4}, payload);
}

void encode_record_header(std::span<const uint8_t> payload, uint8_t out[kRecordHeaderBytes]) {
  store_u32(out, kRecordMagic);
  store_u32(out + 4, static_cast<uint32_t>(payload.size()));
  store_u64(out + 8, record_checksum(out + 4, payload));
}

bool record_length_allowed(const FrameShape& shape, uint32_t payload_bytes, bool compressed) {
  if (compressed) return payload_bytes >= 2 && payload_bytes <= max_record_bytes(shape, true) - kRecordHeaderBytes;
  if (payload_bytes == pose_payload_bytes(shape.vertex_count, shape.input_count, false)) return true;
  return shape.normals && payload_bytes == pose_payload_bytes(shape.vertex_count, shape.input_count, true);
}

uint64_t max_record_bytes(const FrameShape& shape, bool compressed) {
  const uint64_t payload = max_pose_payload_bytes(shape);
  return kRecordHeaderBytes + (compressed ? max_compressed_record_payload(payload) : payload);
}

}  // namespace sinew::hal::output
