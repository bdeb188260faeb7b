// Compact per-joint CAN output: one classic CAN frame (8 data bytes) per rig
// input carrying its index, applied value, JointStatus bits and a 4-bit
// counter (layout in docs/frame-formats.md). Frames are produced into a
// caller's buffer; sending them is the CAN backend's job.
#pragma once

#include <linux/can.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "hal/common/pose_frame.hpp"

namespace sinew::hal::output {

struct CanOutputOptions {
  uint32_t can_id = 0x300;   // identifier shared by all joint frames
  bool extended_id = false;  // 29-bit identifier (CAN_EFF_FLAG)
};

// One decoded joint frame.
struct CanJointFrame {
  uint16_t input = 0;
  int32_t value = 0;    // as applied this tick: binary angle, or Q12.20 for translational inputs
  uint8_t status = 0;   // hal::JointStatus bits
  uint8_t counter = 0;  // tick mod 16
};

class CanFrameEncoder {
 public:
  // Checks the identifier fits its format.
  bool configure(const CanOutputOptions& options, std::string* error);

  // Writes one frame per input of `frame` into `out` and returns how many;
  // 0 if `out` cannot hold them all (a partial set would silently drop
  // joints) or an input index does not fit 16 bits. Never allocates.
  size_t encode(const PoseFrame& frame, std::span<can_frame> out) const;

 private:
  canid_t id_ = 0x300;
};

// Decodes a joint frame; false if it is not one (wrong length or reserved bits set).
bool decode_can_joint_frame(const can_frame& frame, CanJointFrame* out);

}  // namespace sinew::hal::output
