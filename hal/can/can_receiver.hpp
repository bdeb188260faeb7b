// One CAN input: a frame source, a decoder and the receive timeouts, with
// every buffer sized at configure(). poll() is the per-tick call: it drains
// the source, decodes the frames that arrived up to the tick time, and hands
// back the accepted samples and the rejections. Allocation-free per tick.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "frame_decoder.hpp"
#include "frame_source.hpp"
#include "receive_timeouts.hpp"

namespace sinew::hal::can {

struct PollResult {
  std::span<const JointSample> samples;    // accepted, in arrival order
  std::span<const Rejection> rejections;   // in arrival order
  size_t frames = 0;                       // frames decoded by this poll
};

class CanReceiver {
 public:
  // source and decoder must outlive the receiver; the decoder is configured.
  // Installs the decoder's identifiers as the source's filters. frame_capacity
  // bounds the frames handled per poll (more wait in the source's queue).
  bool configure(FrameSource& source, FrameDecoder& decoder, size_t frame_capacity, uint64_t start_ns,
                 std::string* error);

  // Decodes every frame with timestamp <= until_ns; later ones (drained
  // already) are kept for the next poll. now_ns drives the source's reopen
  // back-off. Spans stay valid until the next poll.
  PollResult poll(uint64_t until_ns, uint64_t now_ns);
  PollResult poll(uint64_t now_ns) { return poll(now_ns, now_ns); }

  // Inputs without a valid sample for longer than their timeout at now_ns.
  std::span<const uint16_t> stale_inputs(uint64_t now_ns) { return timeouts_.stale_inputs(now_ns); }
  const ReceiveTimeouts& timeouts() const { return timeouts_; }

  BusState bus_state() const { return source_->bus_state(); }
  const BusCounters& bus_counters() const { return source_->counters(); }
  const FrameDecoder& decoder() const { return *decoder_; }
  size_t held_frames() const { return held_; }

 private:
  FrameSource* source_ = nullptr;
  FrameDecoder* decoder_ = nullptr;
  ReceiveTimeouts timeouts_;
  std::vector<CanFrame> frames_;           // [0, held_) drained but not yet due
  size_t held_ = 0;
  std::vector<JointSample> samples_;
  std::vector<Rejection> rejections_;
  FrameDecode scratch_;
};

}  // namespace sinew::hal::can
