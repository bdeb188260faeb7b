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

// A frame that carries no joint data and closes a cycle: the sender's last
// frame of a set (the tick latches what arrived up to and including it).
// CANopen's SYNC uses 0x080; here the sender puts it after its data frames.
struct SyncFrameOptions {
  bool enabled = false;
  FrameId id{};
};

// What arrived since the last poll (CanReceiver::arrival).
struct ArrivalState {
  bool complete = false;  // a frame with each of the decoder's identifiers
  bool sync = false;      // the sync frame
};

struct PollResult {
  std::span<const JointSample> samples;   // accepted, in arrival order
  std::span<const Rejection> rejections;  // in arrival order
  size_t frames = 0;                      // frames decoded by this poll
};

class CanReceiver {
 public:
  // source and decoder must outlive the receiver; the decoder is configured.
  // Installs the decoder's identifiers as the source's filters. frame_capacity
  // bounds the frames handled per poll (more wait in the source's queue).
  // sync: a sync frame to watch for (its identifier joins the filters; it
  // is never decoded). It must not be one of the decoder's identifiers.
  bool configure(FrameSource& source, FrameDecoder& decoder, size_t frame_capacity, uint64_t start_ns,
                 std::string* error, const SyncFrameOptions& sync = {});

  // Decodes every frame with timestamp <= until_ns; later ones (drained
  // already) are kept for the next poll. now_ns drives the source's reopen
  // back-off. Spans stay valid until the next poll.
  PollResult poll(uint64_t until_ns, uint64_t now_ns);
  PollResult poll(uint64_t now_ns) { return poll(now_ns, now_ns); }
  // Drains the source and reports, of the frames stamped <= now_ns not yet
  // decoded, whether every decoder identifier and the sync frame are among
  // them. Decodes nothing: the frames wait for the next poll. Scans each
  // frame once between polls.
  ArrivalState arrival(uint64_t now_ns);
  bool has_sync() const { return sync_.enabled; }
  uint64_t sync_frames() const { return sync_frames_; }

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
  std::vector<CanFrame> frames_;  // [0, held_) drained but not yet due
  size_t held_ = 0;
  std::vector<JointSample> samples_;
  std::vector<Rejection> rejections_;
  FrameDecode scratch_;
  SyncFrameOptions sync_;
  std::vector<FrameId> filters_;  // the decoder's identifiers, then the sync frame's
  std::vector<uint8_t> seen_;     // per decoder identifier: arrived since the last poll
  size_t seen_count_ = 0;
  size_t scanned_ = 0;  // frames [0, scanned_) already counted into seen_
  bool sync_seen_ = false;
  uint64_t sync_frames_ = 0;
};

}  // namespace sinew::hal::can
