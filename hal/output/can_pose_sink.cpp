#include "can_pose_sink.hpp"

#include "hal/can/kernel_frame.hpp"
#include "hal/common/joint_sample.hpp"

namespace sinew::hal::output {

bool CanPoseSink::open(const CanPoseSinkOptions& options, uint32_t input_count,
                       std::unique_ptr<can::FrameWriter> writer, std::string* error) {
  if (!writer) return *error = "CAN output: no transport", false;
  protocol_ = options.protocol;
  if (protocol_ == CanOutputProtocol::kJointFrames) {
    if (!encoder_.configure(options.frames, error)) return false;
    if (input_count > uint32_t{UINT16_MAX} + 1)
      return *error = "CAN output: " + std::to_string(input_count) + " inputs do not fit the frame's 16-bit index",
             false;
    encoded_.assign(input_count, can_frame{});
    frames_.assign(input_count, can::CanFrame{});
  } else {
    if (input_count > can::kDefaultMaxJoints)
      return *error = "CAN output: " + std::to_string(input_count) + " inputs, more than the joint-stream layout's " +
                      std::to_string(can::kDefaultMaxJoints) + " (protocol = \"joint-frames\" carries up to 65536)",
             false;
    layout_ = can::default_joint_stream_config(input_count, options.fd, options.period_ns);
    if (!can::validate(layout_, error) || !sender_.configure(layout_, error)) return false;
    frames_.assign(layout_.frames.size(), can::CanFrame{});
    values_.assign(can::kJointsPerFdFrame, 0);
    status_.assign(can::kJointsPerFdFrame, 0);
  }
  writer_ = std::move(writer);
  return true;
}

// One record per input in the layout's frames; a stale input (no valid
// sample within its timeout: the value is held) carries the sender-fault
// bit, so a receiver does not take it for a current measurement.
bool CanPoseSink::encode_joint_stream(const PoseFrame& frame) {
  if (frame.input_count > 0 && (frame.input_value == nullptr || frame.input_status == nullptr)) return false;
  for (size_t f = 0; f < layout_.frames.size(); ++f) {
    const std::vector<can::JointChannel>& joints = layout_.frames[f].joints;
    for (size_t s = 0; s < joints.size(); ++s) {
      const uint16_t input = joints[s].input;
      if (input >= frame.input_count) return false;
      values_[s] = frame.input_value[input];
      status_[s] = (frame.input_status[input] & kJointStale) != 0 ? kSampleSenderFault : kSampleOk;
    }
    frames_[f] = sender_.next(f, std::span<const int32_t>(values_.data(), joints.size()),
                              std::span<const uint8_t>(status_.data(), joints.size()), frame.timestamp_ns);
  }
  return true;
}

bool CanPoseSink::write(const PoseFrame& frame) {
  if (!writer_) return false;
  ++ticks_;
  size_t n = 0;
  if (protocol_ == CanOutputProtocol::kJointStream) {
    if (!encode_joint_stream(frame)) {
      ++ticks_incomplete_;
      return false;
    }
    n = frames_.size();
  } else {
    n = encoder_.encode(frame, encoded_);
    if (n != frame.input_count) {
      ++ticks_incomplete_;
      return false;
    }
    for (size_t i = 0; i < n; ++i) can::from_kernel(&encoded_[i], CAN_MTU, frame.timestamp_ns, frames_[i]);
  }
  const size_t sent = writer_->send(std::span<const can::CanFrame>(frames_.data(), n), frame.timestamp_ns);
  if (sent != n) ++ticks_incomplete_;
  return sent == n;
}

void CanPoseSink::flush() {
  if (writer_) writer_->flush();
}

std::string CanPoseSink::status_line() const {
  std::string s = name_ + ": " + std::to_string(ticks_) + " ticks";
  if (ticks_incomplete_ > 0) s += " (" + std::to_string(ticks_incomplete_) + " incomplete)";
  if (writer_) s += "; " + writer_->status_line();
  return s;
}

}  // namespace sinew::hal::output
