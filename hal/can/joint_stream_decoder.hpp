// Receiver side of the default joint-stream protocol: per joint, the CRC,
// the alive counter (repeated / jumped) and the configured range, exactly as
// documented in docs/can-protocol.md. Per-frame work is allocation-free.
#pragma once

#include <string>
#include <vector>

#include "frame_decoder.hpp"
#include "joint_stream_config.hpp"

namespace sinew::hal::can {

class JointStreamDecoder final : public FrameDecoder {
 public:
  // Validates and takes the configuration; resets all counter state.
  bool configure(const JointStreamConfig& config, std::string* error);

  std::span<const ChannelInfo> channels() const override { return channel_info_; }
  std::span<const FrameId> frame_ids() const override { return frame_ids_; }
  bool wants_fd() const override { return wants_fd_; }

 protected:
  void decode_frame(const CanFrame& frame, FrameDecode& out) override;

 private:
  struct JointState {
    JointChannel config;
    uint64_t timeout_ns = 0;
    bool synced = false;        // a counter reference exists
    uint8_t last_counter = 0;   // alive counter of the last authentic record
    uint64_t last_seen_ns = 0;  // when the last intact record (CRC good, counter set) arrived
  };
  struct FrameEntry {
    uint64_t key = 0;  // extended flag << 32 | identifier, sorted
    bool fd = false;
    uint16_t first_joint = 0;  // index into joints_
    uint8_t joint_count = 0;
  };

  const FrameEntry* find(const CanFrame& frame) const;
  void check_record(JointState& joint, std::span<const uint8_t, 8> bytes, uint64_t timestamp_ns, FrameDecode& out);

  std::vector<FrameEntry> frames_;
  std::vector<JointState> joints_;
  std::vector<ChannelInfo> channel_info_;
  std::vector<FrameId> frame_ids_;
  bool wants_fd_ = false;
};

}  // namespace sinew::hal::can
