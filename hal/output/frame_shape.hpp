// The fixed dimensions of a stream of pose frames, known from the rig at
// open(): every sink sizes its buffers from it once, so writes never allocate.
#pragma once

#include <cstddef>
#include <cstdint>

#include "hal/common/pose_frame.hpp"

namespace sinew::hal::output {

struct FrameShape {
  uint32_t vertex_count = 0;
  uint32_t input_count = 0;
  int32_t length_exponent = 0;
  bool normals = false;  // whether frames carry normals (when the frame provides them)

  friend bool operator==(const FrameShape&, const FrameShape&) = default;
};

// The shape a frame has (normals: all three normal arrays are present).
FrameShape shape_of(const PoseFrame& frame);

// Frames larger than this are refused at open(): it bounds every buffer and
// keeps sizes inside the formats' 32-bit length fields.
inline constexpr uint64_t kMaxPayloadBytes = uint64_t{1} << 30;

}  // namespace sinew::hal::output
