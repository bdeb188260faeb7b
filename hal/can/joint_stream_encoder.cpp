#include "joint_stream_encoder.hpp"

namespace sinew::hal::can {

CanFrame encode_classic_joint_frame(uint32_t can_id, bool extended, uint16_t data_id, const JointRecord& record) {
  CanFrame f;
  f.id = can_id;
  f.extended = extended;
  f.len = kJointRecordSize;
  encode_joint_record(data_id, record, std::span<uint8_t, kJointRecordSize>(f.data.data(), kJointRecordSize));
  return f;
}

CanFrame encode_fd_joint_frame(uint32_t can_id, bool extended, std::span<const SlotRecord> slots) {
  CanFrame f;
  f.id = can_id;
  f.extended = extended;
  f.fd = true;
  f.fd_flags = kFdFrameFormat;
  const size_t n = slots.size() > kJointsPerFdFrame ? kJointsPerFdFrame : slots.size();
  f.len = fd_dlc_to_len(fd_len_to_dlc(static_cast<uint8_t>(n * kJointRecordSize)));
  for (size_t k = 0; k < n; ++k) {
    encode_joint_record(slots[k].data_id, slots[k].record,
                        std::span<uint8_t, kJointRecordSize>(f.data.data() + k * kJointRecordSize, kJointRecordSize));
  }
  return f;
}

bool JointStreamSender::configure(const JointStreamConfig& config, std::string* error) {
  if (!validate(config, error)) return false;
  frames_ = config.frames;
  counters_.clear();
  for (const JointFrame& f : frames_) counters_.emplace_back(f.joints.size(), uint8_t{0});
  return true;
}

CanFrame JointStreamSender::next(size_t frame_index, std::span<const int32_t> values, std::span<const uint8_t> status,
                                 uint64_t timestamp_ns) {
  if (frame_index >= frames_.size()) return CanFrame{};
  const JointFrame& jf = frames_[frame_index];
  std::vector<uint8_t>& counters = counters_[frame_index];
  SlotRecord slots[kJointsPerFdFrame];
  for (size_t k = 0; k < jf.joints.size(); ++k) {
    slots[k].data_id = jf.joints[k].data_id;
    slots[k].record.counter = counters[k];
    slots[k].record.value = k < values.size() ? values[k] : 0;
    slots[k].record.status = k < status.size() ? status[k] : uint8_t{0};
    counters[k] = static_cast<uint8_t>((counters[k] + 1) % kAliveCounterModulo);
  }
  CanFrame f = jf.fd
                   ? encode_fd_joint_frame(jf.can_id, jf.extended, std::span<const SlotRecord>(slots, jf.joints.size()))
                   : encode_classic_joint_frame(jf.can_id, jf.extended, slots[0].data_id, slots[0].record);
  f.timestamp_ns = timestamp_ns;
  return f;
}

}  // namespace sinew::hal::can
