#include "frame_decoder.hpp"

namespace sinew::hal::can {

uint64_t ChannelCounters::rejected_total() const {
  uint64_t n = 0;
  for (uint64_t r : rejected) n += r;
  return n;
}

void FrameDecoder::decode(const CanFrame& frame, FrameDecode& out) {
  out.sample_count = 0;
  out.rejection_count = 0;
  if (frame.kind == FrameKind::kError) return;
  decode_frame(frame, out);
  for (const JointSample& s : out.accepted()) {
    if (s.input < by_input_.size()) ++by_input_[s.input].accepted;
  }
  for (const Rejection& r : out.rejected()) {
    const auto reason = static_cast<size_t>(r.reason);
    if (r.input >= 0 && static_cast<size_t>(r.input) < by_input_.size()) {
      ++by_input_[static_cast<size_t>(r.input)].rejected[reason];
    } else {
      ++unassigned_.rejected[reason];
    }
  }
}

const ChannelCounters& FrameDecoder::counters(uint16_t input) const {
  return input < by_input_.size() ? by_input_[input] : zero_;
}

void FrameDecoder::size_counters(std::span<const ChannelInfo> channels) {
  size_t n = 0;
  for (const ChannelInfo& c : channels) n = c.input + 1u > n ? c.input + 1u : n;
  by_input_.assign(n, ChannelCounters{});
  unassigned_ = ChannelCounters{};
}

}  // namespace sinew::hal::can
