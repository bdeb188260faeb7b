// Third-party encoders described by DBC-style signals (configured here, not
// parsed from a .dbc at run time): raw bits → physical value (raw x scale +
// offset) → range check → engine integer. Per-frame work is allocation-free.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine_units.hpp"
#include "frame_decoder.hpp"
#include "signal_bits.hpp"

namespace sinew::hal::can {

struct SignalSpec {
  uint32_t can_id = 0;
  bool extended = false;
  uint16_t start_bit = 0;  // DBC start bit (see signal_bits.hpp for the two conventions)
  uint8_t length = 1;      // 1..64
  ByteOrder byte_order = ByteOrder::kIntel;
  bool is_signed = false;
  double scale = 1.0;  // physical = raw x scale + offset
  double offset = 0.0;
  double min = 0.0;  // accepted physical range, inclusive; required
  double max = 0.0;  //   (DBC's [0|0] "unbounded" is refused)
  PhysicalUnit unit = PhysicalUnit::kDegrees;
  uint16_t input = 0;      // rig input the value feeds
  uint64_t period_ns = 0;  // expected period; timeout 1.5 x period unless timeout_ns
  uint64_t timeout_ns = 0;
};

// Checks one signal: length, placement within 64 bytes, finite non-zero
// scale, a finite physical value for every raw value, a range within what the
// unit can represent. Returns false with a message.
bool validate(const SignalSpec& spec, std::string* error);

// raw field → physical value (finite by construction for a validated spec).
double physical_value(const SignalSpec& spec, uint64_t raw);

class SignalDecoder final : public FrameDecoder {
 public:
  bool configure(const std::vector<SignalSpec>& signals, std::string* error);

  std::span<const ChannelInfo> channels() const override { return channel_info_; }
  std::span<const FrameId> frame_ids() const override { return frame_ids_; }
  bool wants_fd() const override { return wants_fd_; }

 protected:
  void decode_frame(const CanFrame& frame, FrameDecode& out) override;

 private:
  struct Entry {
    uint64_t key = 0;  // extended << 32 | identifier; entries sorted by key
    SignalSpec spec;
    size_t bytes = 0;  // payload bytes the signal needs
  };
  std::vector<Entry> entries_;
  std::vector<ChannelInfo> channel_info_;
  std::vector<FrameId> frame_ids_;
  bool wants_fd_ = false;
};

}  // namespace sinew::hal::can
