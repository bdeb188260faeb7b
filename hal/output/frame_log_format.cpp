#include "frame_log_format.hpp"

#include <cstring>

#include "checksum.hpp"
#include "le_bytes.hpp"
#include "pose_codec.hpp"

namespace sinew::hal::output {

namespace {
constexpr size_t kHeaderChecksumAt = 32;
}

void encode_log_header(const FrameShape& shape, uint8_t out[kLogHeaderBytes]) {
  std::memcpy(out, kLogMagic, sizeof(kLogMagic));
  store_u16(out + 8, kLogVersion);
  store_u16(out + 10, static_cast<uint16_t>(kLogHeaderBytes));
  store_u32(out + 12, shape.normals ? kLogFlagNormals : 0u);
  store_u32(out + 16, shape.vertex_count);
  store_u32(out + 20, shape.input_count);
  store_i32(out + 24, shape.length_exponent);
  store_u32(out + 28, 0);
  store_u64(out + kHeaderChecksumAt, xxh64({out, kHeaderChecksumAt}));
}

bool parse_log_header(std::span<const uint8_t> bytes, FrameShape* shape, std::string* why) {
  if (bytes.size() < kLogHeaderBytes) return *why = "shorter than a frame log header", false;
  const uint8_t* p = bytes.data();
  if (std::memcmp(p, kLogMagic, sizeof(kLogMagic)) != 0) return *why = "not a frame log (bad magic)", false;
  const uint16_t version = load_u16(p + 8);
  if (version != kLogVersion)
    return *why = "frame log version " + std::to_string(version) + " (this build reads version " +
                  std::to_string(kLogVersion) + ")",
           false;
  if (load_u64(p + kHeaderChecksumAt) != xxh64({p, kHeaderChecksumAt}))
    return *why = "frame log header checksum mismatch", false;
  const uint32_t flags = load_u32(p + 12);
  if (load_u16(p + 10) != kLogHeaderBytes || (flags & ~kLogFlagNormals) != 0 || load_u32(p + 28) != 0)
    return *why = "frame log header has unknown fields", false;
  shape->normals = (flags & kLogFlagNormals) != 0;
  shape->vertex_count = load_u32(p + 16);
  shape->input_count = load_u32(p + 20);
  shape->length_exponent = load_i32(p + 24);
  if (max_pose_payload_bytes(*shape) == 0) return *why = "frame log header counts are out of range", false;
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

bool record_length_allowed(const FrameShape& shape, uint32_t payload_bytes) {
  if (payload_bytes == pose_payload_bytes(shape.vertex_count, shape.input_count, false)) return true;
  return shape.normals && payload_bytes == pose_payload_bytes(shape.vertex_count, shape.input_count, true);
}

uint64_t max_record_bytes(const FrameShape& shape) { return kRecordHeaderBytes + max_pose_payload_bytes(shape); }

}  // namespace sinew::hal::output
