// The pose on a CAN bus as an output sink: each frame's inputs, as applied,
// encoded one classic CAN frame per input (can_frames.hpp; layout in
// docs/frame-formats.md) and handed to a CAN transport: SocketCanWriter on
// a board, CandumpFrameWriter (its simulated twin) in tests and replays.
// write() neither blocks nor allocates: its buffers are sized at open().
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "can_frames.hpp"
#include "hal/can/frame_writer.hpp"
#include "hal/common/output_sink.hpp"

namespace sinew::hal::output {

class CanPoseSink final : public OutputSink {
 public:
  // Configuration time: checks the identifier and that every input index
  // fits the frame's 16 bits, and sizes the buffers for input_count inputs.
  bool open(const CanOutputOptions& options, uint32_t input_count, std::unique_ptr<can::FrameWriter> writer,
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
  CanFrameEncoder encoder_;
  std::unique_ptr<can::FrameWriter> writer_;
  std::vector<can_frame> encoded_;
  std::vector<can::CanFrame> frames_;
  std::string name_ = "can";
  uint64_t ticks_ = 0;
  uint64_t ticks_incomplete_ = 0;
};

}  // namespace sinew::hal::output
