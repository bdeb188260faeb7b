#include "reassembler.hpp"

#include <algorithm>
#include <cstring>

namespace sinew::receiver {

namespace {
constexpr uint64_t kRestartGap = 1024;  // further behind than this: the sender started over
constexpr uint64_t kLateWindow = 64;    // bits of Reassembler::late_seen_
}  // namespace

using hal::output::DatagramCheck;
using hal::output::UdpFragment;

Reassembler::Reassembler(const ReassemblerOptions& options)
    : options_(options), slots_(std::max<size_t>(1, options.slots)) {}

bool Reassembler::feed(std::span<const uint8_t> datagram) {
  ++stats_.datagrams;
  delivered_ = {};
  UdpFragment f;
  std::span<const uint8_t> part;
  if (hal::output::parse_udp_datagram(datagram, &f, &part) != DatagramCheck::kOk ||
      f.total_bytes > options_.max_frame_bytes)
    return ++stats_.bad_datagrams, false;
  if (!accept_stream(f.stream_id)) return ++stats_.foreign_datagrams, false;
  if (is_stale(f.sequence)) return false;
  Slot* slot = slot_for(f);
  if (slot == nullptr) return false;
  if (slot->have[f.fragment_index] != 0) return ++stats_.duplicate_fragments, false;
  std::memcpy(slot->bytes.data() + f.payload_offset, part.data(), part.size());
  slot->have[f.fragment_index] = 1;
  slot->bytes_received += part.size();
  if (++slot->fragments_received < slot->fragment_count) return false;
  if (slot->bytes_received != slot->total_bytes) {  // fragments overlap or leave holes: not a frame we can trust
    ++stats_.inconsistent_fragments;
    discard(*slot);
    return false;
  }
  deliver(*slot);
  return true;
}

bool Reassembler::accept_stream(uint32_t stream_id) {
  if (options_.stream_id != 0 && stream_id != options_.stream_id) return false;
  if (have_stream_ && stream_id == stream_id_) return true;
  if (have_stream_) {
    ++stats_.stream_restarts;
    for (Slot& s : slots_)
      if (s.busy) discard(s);
    have_delivered_ = false;
    late_seen_ = 0;
  }
  have_stream_ = true;
  stream_id_ = stream_id;
  return true;
}

bool Reassembler::is_stale(uint64_t sequence) {
  if (!have_delivered_ || sequence > last_delivered_) return false;
  if (sequence == last_delivered_) return ++stats_.duplicate_fragments, true;
  const uint64_t behind = last_delivered_ - sequence;
  if (behind > kRestartGap) {  // same stream id, sequence started over
    ++stats_.stream_restarts;
    for (Slot& s : slots_)
      if (s.busy) discard(s);
    have_delivered_ = false;
    late_seen_ = 0;
    return false;
  }
  ++stats_.stale_fragments;
  const uint64_t bit = behind - 1;
  if (bit < kLateWindow && (late_seen_ & (uint64_t{1} << bit)) == 0) {
    late_seen_ |= uint64_t{1} << bit;
    ++stats_.frames_out_of_order;
  }
  return true;
}

Reassembler::Slot* Reassembler::slot_for(const UdpFragment& f) {
  Slot* free_slot = nullptr;
  Slot* oldest = nullptr;
  for (Slot& s : slots_) {
    if (s.busy && s.sequence == f.sequence) {
      if (s.fragment_count != f.fragment_count || s.total_bytes != f.total_bytes)
        return ++stats_.inconsistent_fragments, nullptr;
      return &s;
    }
    if (!s.busy && free_slot == nullptr) free_slot = &s;
    if (s.busy && (oldest == nullptr || s.sequence < oldest->sequence)) oldest = &s;
  }
  if (free_slot == nullptr) {
    // All slots busy: the oldest frame gives way, unless the newcomer is older still.
    if (oldest == nullptr || f.sequence < oldest->sequence) return ++stats_.stale_fragments, nullptr;
    discard(*oldest);
    free_slot = oldest;
  }
  Slot& s = *free_slot;
  s.busy = true;
  s.sequence = f.sequence;
  s.fragment_count = f.fragment_count;
  s.fragments_received = 0;
  s.total_bytes = f.total_bytes;
  s.bytes_received = 0;
  s.have.assign(f.fragment_count, 0);
  s.bytes.resize(f.total_bytes);  // keeps its capacity: a steady stream stops allocating
  return &s;
}

void Reassembler::deliver(Slot& slot) {
  const uint64_t sequence = slot.sequence;
  if (have_delivered_) {
    const uint64_t advance = sequence - last_delivered_;
    stats_.frames_lost += advance - 1;
    late_seen_ = advance >= kLateWindow ? 0 : late_seen_ << advance;
  }
  have_delivered_ = true;
  last_delivered_ = sequence;
  ++stats_.frames_delivered;
  delivered_storage_.swap(slot.bytes);
  delivered_ = delivered_storage_;
  slot.busy = false;
  for (Slot& s : slots_)
    if (s.busy && s.sequence < sequence) discard(s);
}

void Reassembler::discard(Slot& slot) {
  slot.busy = false;
  ++stats_.frames_incomplete;
}

}  // namespace sinew::receiver
