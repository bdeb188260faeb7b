#include "pose_codec.hpp"

#include "le_bytes.hpp"

namespace sinew::hal::output {

uint64_t pose_payload_bytes(uint32_t vertex_count, uint32_t input_count, bool normals) {
  const uint64_t per_vertex = normals ? 24 : 12;
  const uint64_t bytes = kPoseHeaderBytes + per_vertex * vertex_count + 5ull * input_count;
  return bytes > kMaxPayloadBytes ? 0 : bytes;
}

uint64_t max_pose_payload_bytes(const FrameShape& shape) {
  return pose_payload_bytes(shape.vertex_count, shape.input_count, shape.normals);
}

namespace {

bool arrays_present(const PoseFrame& f) {
  if (f.vertex_count > 0)
    for (const int32_t* p : f.position)
      if (p == nullptr) return false;
  return f.input_count == 0 || (f.input_value != nullptr && f.input_status != nullptr);
}

}  // namespace

size_t encode_pose(const PoseFrame& frame, const FrameShape& shape, std::span<uint8_t> out) {
  if (frame.vertex_count != shape.vertex_count || frame.input_count != shape.input_count ||
      frame.length_exponent != shape.length_exponent || !arrays_present(frame))
    return 0;
  const bool normals = shape.normals && shape_of(frame).normals;
  const uint64_t bytes = pose_payload_bytes(frame.vertex_count, frame.input_count, normals);
  if (bytes == 0 || bytes > out.size()) return 0;

  uint8_t* p = out.data();
  store_u64(p, frame.tick);
  store_u64(p + 8, frame.timestamp_ns);
  store_i32(p + 16, frame.length_exponent);
  store_u32(p + 20, frame.vertex_count);
  store_u32(p + 24, frame.input_count);
  store_u32(p + 28, normals ? kPoseFlagNormals : 0u);
  p += kPoseHeaderBytes;
  const size_t n = frame.vertex_count;
  for (const int32_t* axis : frame.position) {
    store_i32_array(p, axis, n);
    p += 4 * n;
  }
  if (normals) {
    for (const int32_t* axis : frame.normal) {
      store_i32_array(p, axis, n);
      p += 4 * n;
    }
  }
  store_i32_array(p, frame.input_value, frame.input_count);
  p += 4 * size_t{frame.input_count};
  for (uint32_t i = 0; i < frame.input_count; ++i) p[i] = frame.input_status[i];
  return static_cast<size_t>(bytes);
}

}  // namespace sinew::hal::output
