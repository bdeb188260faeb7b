#include "can_receiver.hpp"

#include <algorithm>

namespace sinew::hal::can {

namespace {

bool is_frame(const CanFrame& f, const FrameId& id) {
  return f.kind != FrameKind::kError && f.id == id.id && f.extended == id.extended;
}

}  // namespace

bool CanReceiver::configure(FrameSource& source, FrameDecoder& decoder, size_t frame_capacity, uint64_t start_ns,
                            std::string* error, const SyncFrameOptions& sync) {
  if (frame_capacity == 0) {
    if (error != nullptr) *error = "can receiver: frame capacity must be at least 1";
    return false;
  }
  const std::span<const FrameId> ids = decoder.frame_ids();
  if (sync.enabled && std::find(ids.begin(), ids.end(), sync.id) != ids.end()) {
    if (error != nullptr) *error = "can receiver: the sync frame's identifier carries joint data";
    return false;
  }
  filters_.assign(ids.begin(), ids.end());
  // An empty filter list accepts everything: the sync frame then needs no entry.
  if (sync.enabled && !filters_.empty()) filters_.push_back(sync.id);
  if (!source.set_filters(filters_, error)) return false;
  sync_ = sync;
  seen_.assign(ids.size(), 0);
  seen_count_ = 0;
  scanned_ = 0;
  sync_seen_ = false;
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
    if (sync_.enabled && is_frame(frames_[decoded], sync_.id)) {  // no joint data: not the decoder's
      ++sync_frames_;
      ++decoded;
      continue;
    }
    decoder_->decode(frames_[decoded], scratch_);
    for (const JointSample& s : scratch_.accepted()) {
      samples_[n_samples++] = s;
      timeouts_.on_sample(s.input, s.timestamp_ns);
    }
    for (const Rejection& r : scratch_.rejected()) rejections_[n_rejections++] = r;
    ++decoded;
  }
  std::move(frames_.begin() + static_cast<std::ptrdiff_t>(decoded),
            frames_.begin() + static_cast<std::ptrdiff_t>(total), frames_.begin());
  held_ = total - decoded;
  // The frames held for later are scanned again by the next arrival().
  std::fill(seen_.begin(), seen_.end(), uint8_t{0});
  seen_count_ = 0;
  scanned_ = 0;
  sync_seen_ = false;

  result.samples = {samples_.data(), n_samples};
  result.rejections = {rejections_.data(), n_rejections};
  result.frames = decoded;
  return result;
}

ArrivalState CanReceiver::arrival(uint64_t now_ns) {
  ArrivalState state;
  if (source_ == nullptr) return state;
  const size_t drained = source_->drain(std::span<CanFrame>(frames_).subspan(held_), now_ns);
  for (size_t i = held_; i < held_ + drained; ++i) frames_[i].timestamp_ns = std::min(frames_[i].timestamp_ns, now_ns);
  held_ += drained;
  const std::span<const FrameId> ids = decoder_->frame_ids();
  // Frames arrive in order: the first one stamped after now ends the scan.
  for (; scanned_ < held_ && frames_[scanned_].timestamp_ns <= now_ns; ++scanned_) {
    const CanFrame& f = frames_[scanned_];
    if (sync_.enabled && is_frame(f, sync_.id)) {
      sync_seen_ = true;
      continue;
    }
    for (size_t k = 0; k < ids.size(); ++k) {
      if (!is_frame(f, ids[k]) || seen_[k] != 0) continue;
      seen_[k] = 1;
      ++seen_count_;
      break;
    }
  }
  state.complete = !ids.empty() && seen_count_ == ids.size();
  state.sync = sync_seen_;
  return state;
}

}  // namespace sinew::hal::can
