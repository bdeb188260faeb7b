// The pose payload: one PoseFrame as little-endian bytes, shared by the frame
// log (one payload per record) and the UDP stream (one payload per frame,
// fragmented). Layout in docs/frame-formats.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "frame_shape.hpp"
#include "hal/common/pose_frame.hpp"

namespace sinew::hal::output {

inline constexpr size_t kPoseHeaderBytes = 32;
inline constexpr uint32_t kPoseFlagNormals = 1u << 0;

// Bytes of one payload; 0 when it would exceed kMaxPayloadBytes.
uint64_t pose_payload_bytes(uint32_t vertex_count, uint32_t input_count, bool normals);
// The largest payload a stream of this shape produces (normals included if the shape has them).
uint64_t max_pose_payload_bytes(const FrameShape& shape);

// Encodes `frame` into `out`; normals are written when the shape has them and
// the frame provides them. Returns the bytes written, or 0 if the frame does
// not match `shape` (counts, length exponent, missing arrays) or `out` is too
// small. Never allocates.
size_t encode_pose(const PoseFrame& frame, const FrameShape& shape, std::span<uint8_t> out);

}  // namespace sinew::hal::output
