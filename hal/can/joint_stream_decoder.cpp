#include "joint_stream_decoder.hpp"

#include <algorithm>

#include "joint_record.hpp"

namespace sinew::hal::can {

namespace {
uint64_t key_of(uint32_t id, bool extended) { return (static_cast<uint64_t>(extended) << 32) | id; }

int32_t input_of(const JointChannel& j) { return static_cast<int32_t>(j.input); }
}  // namespace

bool JointStreamDecoder::configure(const JointStreamConfig& config, std::string* error) {
  if (!validate(config, error)) return false;
  frames_.clear();
  joints_.clear();
  channel_info_.clear();
  frame_ids_.clear();
  wants_fd_ = false;
  for (const JointFrame& f : config.frames) {
    FrameEntry e;
    e.key = key_of(f.can_id, f.extended);
    e.fd = f.fd;
    e.first_joint = static_cast<uint16_t>(joints_.size());
    e.joint_count = static_cast<uint8_t>(f.joints.size());
    frames_.push_back(e);
    frame_ids_.push_back({f.can_id, f.extended});
    wants_fd_ = wants_fd_ || f.fd;
    for (const JointChannel& j : f.joints) {
      JointState s;
      s.config = j;
      s.timeout_ns = resolved_timeout_ns(j);
      joints_.push_back(s);
      channel_info_.push_back({j.input, s.timeout_ns});
    }
  }
  std::sort(frames_.begin(), frames_.end(), [](const FrameEntry& a, const FrameEntry& b) { return a.key < b.key; });
  size_counters(channel_info_);
  return true;
}

const JointStreamDecoder::FrameEntry* JointStreamDecoder::find(const CanFrame& frame) const {
  const uint64_t key = key_of(frame.id, frame.extended);
  auto it =
      std::lower_bound(frames_.begin(), frames_.end(), key, [](const FrameEntry& e, uint64_t k) { return e.key < k; });
  return it != frames_.end() && it->key == key ? &*it : nullptr;
}

void JointStreamDecoder::decode_frame(const CanFrame& frame, FrameDecode& out) {
  const FrameEntry* entry = find(frame);
  if (entry == nullptr) {
    out.add_rejection(kNoInput, RejectReason::kUnknownId);
    return;
  }
  // Wrong kind, wrong format or too short for its joints: nothing in it can be
  // trusted, so every joint the frame should carry gets one malformed count.
  const size_t needed = size_t{entry->joint_count} * kJointRecordSize;
  const bool shape_ok = frame.kind == FrameKind::kData && frame.fd == entry->fd &&
                        (entry->fd ? frame.len >= needed : frame.len == kJointRecordSize);
  for (uint8_t k = 0; k < entry->joint_count; ++k) {
    JointState& joint = joints_[entry->first_joint + k];
    if (!shape_ok) {
      out.add_rejection(input_of(joint.config), RejectReason::kMalformed);
      continue;
    }
    check_record(joint, std::span<const uint8_t, 8>(frame.data.data() + k * kJointRecordSize, 8), frame.timestamp_ns,
                 out);
  }
}

void JointStreamDecoder::check_record(JointState& joint, std::span<const uint8_t, 8> bytes, uint64_t timestamp_ns,
                                      FrameDecode& out) {
  const int32_t input = input_of(joint.config);
  JointRecord record;
  switch (decode_joint_record(joint.config.data_id, bytes, record)) {
    case RecordCheck::kOk:
      break;
    case RecordCheck::kBadCrc:
      out.add_rejection(input, RejectReason::kBadCrc);
      return;
    case RecordCheck::kInvalidCounter:
    case RecordCheck::kReservedNotZero:
      out.add_rejection(input, RejectReason::kMalformed);
      return;
  }
  // A joint silent for longer than its timeout restarts its counter check:
  // after 15 or more lost frames the counter distance means nothing. Silence
  // is measured from the last intact record, accepted or not, so a sender
  // whose counter is stuck keeps being rejected (it is not silent).
  const bool silent_too_long = joint.timeout_ns != 0 && timestamp_ns > joint.last_seen_ns &&
                               timestamp_ns - joint.last_seen_ns > joint.timeout_ns;
  if (joint.synced && !silent_too_long) {
    const uint8_t delta = alive_counter_delta(joint.last_counter, record.counter);
    if (delta == 0) {
      joint.last_seen_ns = timestamp_ns;
      out.add_rejection(input, RejectReason::kRepeatedCounter);
      return;
    }
    if (delta > joint.config.max_counter_delta) {
      // Resynchronise on the jumped counter: the next consecutive record is
      // accepted, so a burst of lost frames costs exactly one sample.
      joint.last_counter = record.counter;
      joint.last_seen_ns = timestamp_ns;
      out.add_rejection(input, RejectReason::kCounterJump);
      return;
    }
  }
  joint.synced = true;
  joint.last_counter = record.counter;
  joint.last_seen_ns = timestamp_ns;
  if (record.value < joint.config.min || record.value > joint.config.max) {
    out.add_rejection(input, RejectReason::kOutOfRange);
    return;
  }
  out.add_sample({joint.config.input, record.value, timestamp_ns, record.status});
}

}  // namespace sinew::hal::can
