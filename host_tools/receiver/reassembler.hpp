// Reassembles UDP stream datagrams into frame payloads (no sockets: fed one
// datagram at a time, so it is tested without a network).
//
// Policy: a few frames may be in flight at once (fragments of consecutive
// frames interleave or arrive out of order). When a frame completes it is
// delivered, and every older unfinished frame is discarded: once a newer
// frame is out, an older one is stale. Fragments of frames older than the
// last delivered one are discarded and counted as out of order.
//
// Counters satisfy: frames_delivered + frames_lost = last delivered sequence
// - first delivered sequence + 1 (per stream run). frames_incomplete and
// frames_out_of_order explain some of the lost ones (out-of-order frames are
// recognised up to 64 sequence numbers behind; later ones count only as
// stale fragments).
//
// A sender restart shows as a new stream id (senders pick a random one), or,
// with a fixed id, as a sequence more than 1024 behind the last delivered one:
// either resets the sequence tracking.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "hal/output/udp_datagram.hpp"

namespace sinew::receiver {

struct ReassemblerOptions {
  uint32_t stream_id = 0;                // accept only this stream (0: follow whichever stream is sending)
  size_t slots = 4;                      // frames assembled at once
  uint32_t max_frame_bytes = 64u << 20;  // larger frames are refused (bounds memory)
};

struct ReceiverStats {
  uint64_t datagrams = 0;
  uint64_t bad_datagrams = 0;           // failed parse or checksum
  uint64_t foreign_datagrams = 0;       // another stream than the one accepted
  uint64_t inconsistent_fragments = 0;  // disagree with earlier fragments of their frame
  uint64_t duplicate_fragments = 0;
  uint64_t stale_fragments = 0;  // for frames older than the last delivered (or no slot left)
  uint64_t frames_delivered = 0;
  uint64_t frames_lost = 0;          // sequence numbers skipped between delivered frames
  uint64_t frames_incomplete = 0;    // partly received frames discarded
  uint64_t frames_out_of_order = 0;  // frames that arrived after a newer one was delivered
  uint64_t stream_restarts = 0;      // a new stream id took over (sender restarted)
};

class Reassembler {
 public:
  explicit Reassembler(const ReassemblerOptions& options = {});

  // Feeds one datagram; true when it completed a frame, then readable through
  // the accessors below until the next feed().
  bool feed(std::span<const uint8_t> datagram);

  std::span<const uint8_t> frame_payload() const { return delivered_; }
  uint64_t frame_sequence() const { return last_delivered_; }
  uint32_t stream_id() const { return stream_id_; }
  const ReceiverStats& stats() const { return stats_; }

 private:
  struct Slot {
    bool busy = false;
    uint64_t sequence = 0;
    uint16_t fragment_count = 0;
    uint16_t fragments_received = 0;
    uint32_t total_bytes = 0;
    uint64_t bytes_received = 0;
    std::vector<uint8_t> have;  // per fragment: received?
    std::vector<uint8_t> bytes;
  };

  bool accept_stream(uint32_t stream_id);
  bool is_stale(uint64_t sequence);
  Slot* slot_for(const hal::output::UdpFragment& f);
  void deliver(Slot& slot);
  void discard(Slot& slot);

  ReassemblerOptions options_;
  std::vector<Slot> slots_;
  std::vector<uint8_t> delivered_storage_;
  std::span<const uint8_t> delivered_;
  uint32_t stream_id_ = 0;
  bool have_stream_ = false;
  bool have_delivered_ = false;
  uint64_t last_delivered_ = 0;
  uint64_t late_seen_ = 0;  // bit d: sequence last_delivered_ - 1 - d was already counted as out of order
  ReceiverStats stats_;
};

}  // namespace sinew::receiver
