// Host-side decoding of a pose payload into owned arrays (allocates; reused
// vectors keep their capacity, so a steady stream stops allocating).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hal/common/pose_frame.hpp"

namespace sinew::hal::output {

struct DecodedPose {
  uint64_t tick = 0;
  uint64_t timestamp_ns = 0;
  int32_t length_exponent = 0;
  uint32_t vertex_count = 0;
  uint32_t input_count = 0;
  bool has_normals = false;
  std::vector<int32_t> position[3];
  std::vector<int32_t> normal[3];  // empty unless has_normals
  std::vector<int32_t> input_value;
  std::vector<uint8_t> input_status;

  // A PoseFrame pointing into this object (valid while it lives unchanged).
  PoseFrame view() const;
};

// Decodes one payload; false (with the reason in *why) when the bytes are not
// exactly one well-formed payload.
bool decode_pose(std::span<const uint8_t> bytes, DecodedPose* out, std::string* why);

}  // namespace sinew::hal::output
