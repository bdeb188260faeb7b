#include "can_pose_sink.hpp"

#include "hal/can/kernel_frame.hpp"

namespace sinew::hal::output {

bool CanPoseSink::open(const CanOutputOptions& options, uint32_t input_count, std::unique_ptr<can::FrameWriter> writer,
                       std::string* error) {
  if (!encoder_.configure(options, error)) return false;
  if (input_count > uint32_t{UINT16_MAX} + 1)
    return *error = "CAN output: " + std::to_string(input_count) + " inputs do not fit the frame's 16-bit index", false;
  if (!writer) return *error = "CAN output: no transport", false;
  writer_ = std::move(writer);
  encoded_.assign(input_count, can_frame{});
  frames_.assign(input_count, can::CanFrame{});
  return true;
}

bool CanPoseSink::write(const PoseFrame& frame) {
  if (!writer_) return false;
  ++ticks_;
  const size_t n = encoder_.encode(frame, encoded_);
  if (n != frame.input_count) {
    ++ticks_incomplete_;
    return false;
  }
  for (size_t i = 0; i < n; ++i) can::from_kernel(&encoded_[i], CAN_MTU, frame.timestamp_ns, frames_[i]);
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
