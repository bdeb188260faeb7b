// The pose on a CAN bus as an output sink: each tick's inputs, as applied,
// handed to a CAN transport (SocketCanWriter on a board, CandumpFrameWriter,
// its simulated twin, in tests and replays) in one of two encodings:
//  - kJointStream: the joint-stream protocol sinew's CAN sources read
//    (docs/can-protocol.md; hal/can/joint_stream_encoder.hpp): per input a
//    record with its CRC and alive counter in the default layout (classic:
//    input i on 0x100 + i; CAN FD: eight per frame on 0x180 + i / 8), so
//    another node, or another sinewd's CAN source, follows the rig. An input
//    that is stale (no valid sample within its timeout, its value held) is
//    sent with the sender-fault status bit.
//  - kJointFrames: one compact frame per input on one identifier, with its
//    status bits and the tick's counter (can_frames.hpp;
//    docs/frame-formats.md).
// write() neither blocks nor allocates: its buffers are sized at open().
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "can_frames.hpp"
#include "hal/can/frame_writer.hpp"
#include "hal/can/joint_stream_config.hpp"
#include "hal/can/joint_stream_encoder.hpp"
#include "hal/common/output_sink.hpp"

namespace sinew::hal::output {

enum class CanOutputProtocol : uint8_t { kJointStream, kJointFrames };

struct CanPoseSinkOptions {
  CanOutputProtocol protocol = CanOutputProtocol::kJointStream;
  bool fd = false;          // kJointStream: packed CAN FD frames, eight inputs each
  uint64_t period_ns = 0;   // kJointStream: the tick period, for the layout's record
  CanOutputOptions frames;  // kJointFrames: the identifier
};

class CanPoseSink final : public OutputSink {
 public:
  // Configuration time: checks the identifier or the joint-stream layout
  // (at most 128 inputs, the default layout's), and sizes the buffers for
  // input_count inputs.
  bool open(const CanPoseSinkOptions& options, uint32_t input_count, std::unique_ptr<can::FrameWriter> writer,
            std::string* error);
  void set_name(std::string name) { name_ = std::move(name); }

  const char* name() const override { return name_.c_str(); }
  // Sends every input's frame of this tick, stamped with the frame's time;
  // false when any was dropped (the transport counts them).
  bool write(const PoseFrame& frame) override;
  void flush() override;
  std::string status_line() const override;

  uint64_t ticks_written() const { return ticks_; }
  uint64_t ticks_incomplete() const { return ticks_incomplete_; }

 private:
  bool encode_joint_stream(const PoseFrame& frame);

  CanOutputProtocol protocol_ = CanOutputProtocol::kJointStream;
  CanFrameEncoder encoder_;
  can::JointStreamConfig layout_;
  can::JointStreamSender sender_;
  std::vector<int32_t> values_;  // one joint-stream frame's values and statuses
  std::vector<uint8_t> status_;
  std::unique_ptr<can::FrameWriter> writer_;
  std::vector<can_frame> encoded_;
  std::vector<can::CanFrame> frames_;
  std::string name_ = "can";
  uint64_t ticks_ = 0;
  uint64_t ticks_incomplete_ = 0;
};

}  // namespace sinew::hal::output
