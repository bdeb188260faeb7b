#include "pose_decode.hpp"

#include "le_bytes.hpp"
#include "pose_codec.hpp"

namespace sinew::hal::output {

PoseFrame DecodedPose::view() const {
  PoseFrame f;
  f.tick = tick;
  f.timestamp_ns = timestamp_ns;
  f.length_exponent = length_exponent;
  f.vertex_count = vertex_count;
  f.input_count = input_count;
  for (int c = 0; c < 3; ++c) {
    f.position[c] = position[c].data();
    f.normal[c] = has_normals ? normal[c].data() : nullptr;
  }
  f.input_value = input_value.data();
  f.input_status = input_status.data();
  return f;
}

bool decode_pose(std::span<const uint8_t> bytes, DecodedPose* out, std::string* why) {
  if (bytes.size() < kPoseHeaderBytes) return *why = "payload shorter than its header", false;
  const uint8_t* p = bytes.data();
  const uint32_t vertex_count = load_u32(p + 20);
  const uint32_t input_count = load_u32(p + 24);
  const uint32_t flags = load_u32(p + 28);
  if ((flags & ~kPoseFlagNormals) != 0) return *why = "unknown payload flags", false;
  const bool normals = (flags & kPoseFlagNormals) != 0;
  const uint64_t expected = pose_payload_bytes(vertex_count, input_count, normals);
  if (expected == 0 || expected != bytes.size()) return *why = "payload size does not match its counts", false;

  out->tick = load_u64(p);
  out->timestamp_ns = load_u64(p + 8);
  out->length_exponent = load_i32(p + 16);
  out->vertex_count = vertex_count;
  out->input_count = input_count;
  out->has_normals = normals;
  p += kPoseHeaderBytes;
  const size_t n = vertex_count;
  for (auto& axis : out->position) {
    axis.resize(n);
    load_i32_array(axis.data(), p, n);
    p += 4 * n;
  }
  for (auto& axis : out->normal) {
    axis.resize(normals ? n : 0);
    if (!normals) continue;
    load_i32_array(axis.data(), p, n);
    p += 4 * n;
  }
  out->input_value.resize(input_count);
  load_i32_array(out->input_value.data(), p, input_count);
  p += 4 * size_t{input_count};
  out->input_status.assign(p, p + input_count);
  return true;
}

}  // namespace sinew::hal::output
