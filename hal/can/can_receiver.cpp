#include "can_receiver.hpp"

#include <algorithm>

namespace sinew::hal::can {

bool CanReceiver::configure(FrameSource& source, FrameDecoder& decoder, size_t frame_capacity, uint64_t start_ns,
                            std::string* error) {
  if (frame_capacity == 0) {
    if (error != nullptr) *error = "can receiver: frame capacity must be at least 1";
    return false;
  }
  if (!source.set_filters(decoder.frame_ids(), error)) return false;
  source_ = &source;
  decoder_ = &decoder;
  timeouts_.configure(decoder.channels(), start_ns);
  frames_.assign(frame_capacity, CanFrame{});
  held_ = 0;
  samples_.assign(frame_capacity * kMaxSamplesPerFrame, JointSample{});
  rejections_.assign(frame_capacity * kMaxSamplesPerFrame, Rejection{});
  return true;
}

PollResult CanReceiver::poll(uint64_t until_ns, uint64_t now_ns) {
  PollResult result;
  if (source_ == nullptr) return result;
  const size_t drained = source_->drain(std::span<CanFrame>(frames_).subspan(held_), now_ns);
  const size_t total = held_ + drained;
  // Nothing can have arrived after now: a later stamp (clock offset error)
  // would otherwise hold the queue back indefinitely.
  for (size_t i = held_; i < total; ++i) frames_[i].timestamp_ns = std::min(frames_[i].timestamp_ns, now_ns);

  size_t n_samples = 0;
  size_t n_rejections = 0;
  size_t decoded = 0;
  // Frames arrive in order, so the first frame past until_ns ends this tick.
  while (decoded < total && frames_[decoded].timestamp_ns <= until_ns) {
    decoder_->decode(frames_[decoded], scratch_);
    for (const JointSample& s : scratch_.accepted()) {
      samples_[n_samples++] = s;
      timeouts_.on_sample(s.input, s.timestamp_ns);
    }
    for (const Rejection& r : scratch_.rejected()) rejections_[n_rejections++] = r;
    ++decoded;
  }
  std::move(frames_.begin() + static_cast<std::ptrdiff_t>(decoded), frames_.begin() + static_cast<std::ptrdiff_t>(total),
            frames_.begin());
  held_ = total - decoded;

  result.samples = {samples_.data(), n_samples};
  result.rejections = {rejections_.data(), n_rejections};
  result.frames = decoded;
  return result;
}

}  // namespace sinew::hal::can
