// Sender side of the default joint-stream protocol: frame builders with an
// explicit counter (tests craft faults with them) and a stateful sender that
// advances each joint's alive counter (the simulated rig, firmware outputs).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "can_frame.hpp"
#include "joint_record.hpp"
#include "joint_stream_config.hpp"

namespace sinew::hal::can {

struct SlotRecord {
  uint16_t data_id = 0;
  JointRecord record;
};

// Classic CAN: one joint, 8 bytes.
CanFrame encode_classic_joint_frame(uint32_t can_id, bool extended, uint16_t data_id, const JointRecord& record);

// CAN FD: records in slots 0..n-1 (n <= 8); the length is the smallest CAN FD
// length that holds them, padding bytes are zero.
CanFrame encode_fd_joint_frame(uint32_t can_id, bool extended, std::span<const SlotRecord> slots);

class JointStreamSender {
 public:
  bool configure(const JointStreamConfig& config, std::string* error);
  size_t frame_count() const { return frames_.size(); }

  // Frame `frame_index` of the configuration carrying `values` (one per joint
  // of that frame, in slot order) and optional per-joint status; advances the
  // alive counters. Missing values are sent as 0.
  CanFrame next(size_t frame_index, std::span<const int32_t> values, std::span<const uint8_t> status = {},
                uint64_t timestamp_ns = 0);

 private:
  std::vector<JointFrame> frames_;
  std::vector<std::vector<uint8_t>> counters_;  // per frame, per slot
};

}  // namespace sinew::hal::can
