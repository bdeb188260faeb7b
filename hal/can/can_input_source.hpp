// A CAN input as the runtime sees it: a frame source (SocketCAN, the
// simulated bus, a candump replay) and a decoder (default joint stream or
// DBC-style signals) behind hal's InputSource. latch() decodes the frames
// received up to the tick time; rejections go to the input health; the bus
// state maps to the source state (error-warning/passive: degraded; bus-off,
// interface down: down, while the source reopens with back-off).
#pragma once

#include <memory>
#include <string>

#include "can_receiver.hpp"
#include "frame_decoder.hpp"
#include "frame_source.hpp"
#include "hal/common/input_source.hpp"

namespace sinew::hal::can {

class CanInputSource final : public InputSource {
 public:
  // Takes ownership of both; configures the receiver (kernel filters from the
  // decoder's identifiers). frame_capacity bounds the frames decoded per tick.
  // sync: a sync frame that closes each cycle (can_receiver.hpp), if any.
  static std::unique_ptr<CanInputSource> create(std::string name, std::unique_ptr<FrameSource> source,
                                                std::unique_ptr<FrameDecoder> decoder, size_t frame_capacity,
                                                uint64_t start_ns, std::string* error,
                                                const SyncFrameOptions& sync = {});

  const char* name() const override { return name_.c_str(); }
  size_t latch(uint64_t until_ns, std::span<JointSample> out, InputHealth& health) override;
  SourceState state() const override;
  std::string status_line() const override;
  // Complete: a frame of each of the decoder's identifiers has arrived;
  // sync: the sync frame has (when one is configured).
  uint8_t arrival_signals() const override;
  Arrival arrival(uint64_t now_ns) override;

  FrameSource& frame_source() { return *source_; }
  const FrameDecoder& decoder() const { return *decoder_; }

 private:
  CanInputSource() = default;

  std::string name_;
  std::unique_ptr<FrameSource> source_;
  std::unique_ptr<FrameDecoder> decoder_;
  CanReceiver receiver_;
};

}  // namespace sinew::hal::can
