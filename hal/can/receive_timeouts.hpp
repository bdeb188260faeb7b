// Receive timeouts in the CANopen manner (consumer heartbeat / RPDO event
// timer): each input expects a valid sample at least every timeout_ns; past
// that it is stale until the next valid sample. Arrays sized at configure().
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "frame_decoder.hpp"

namespace sinew::hal::can {

class ReceiveTimeouts {
 public:
  // Inputs with timeout 0 are never stale. The clock starts at start_ns: an
  // input that never sends goes stale one timeout after start.
  void configure(std::span<const ChannelInfo> channels, uint64_t start_ns);

  void on_sample(uint16_t input, uint64_t timestamp_ns);

  // Inputs stale at now_ns, ascending; valid until the next call.
  std::span<const uint16_t> stale_inputs(uint64_t now_ns);
  bool is_stale(uint16_t input, uint64_t now_ns) const;
  uint64_t stale_events() const { return stale_events_; }  // transitions into stale

 private:
  struct Entry {
    uint16_t input = 0;
    uint64_t timeout_ns = 0;
    uint64_t last_valid_ns = 0;
    bool stale = false;
  };
  std::vector<Entry> entries_;    // sorted by input
  std::vector<int32_t> slot_of_;  // input → index into entries_, -1 if none
  std::vector<uint16_t> stale_;   // capacity = entries_.size()
  uint64_t stale_events_ = 0;
};

}  // namespace sinew::hal::can
