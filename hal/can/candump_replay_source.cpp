#include "candump_replay_source.hpp"

#include <algorithm>

namespace sinew::hal::can {

bool CandumpReplaySource::load(const CandumpReplayOptions& options, uint64_t start_ns, std::string* error) {
  CandumpLog log;
  if (!read_candump_file(options.path, log, error)) return false;
  errors_ = std::move(log.errors);
  frames_.clear();
  bool have_origin = options.has_origin;
  uint64_t origin = options.origin_ns;
  for (const LoggedFrame& logged : log.frames) {
    if (!options.interface.empty() && logged.interface != options.interface) continue;
    if (!have_origin) {
      origin = logged.frame.timestamp_ns;
      have_origin = true;
    }
    CanFrame frame = logged.frame;
    const uint64_t t = frame.timestamp_ns;
    frame.timestamp_ns = start_ns + (t > origin ? t - origin : 0);
    frames_.push_back(frame);
  }
  if (frames_.empty()) {
    *error = options.path + ": no frame" + (options.interface.empty() ? "" : " on interface " + options.interface) +
             " (" + std::to_string(log.lines) + " lines, " + std::to_string(errors_.size()) + " unreadable)";
    return false;
  }
  // A log is written in arrival order; a reordered one would replay out of
  // time order, which the receivers cannot hold: refuse it.
  for (size_t i = 1; i < frames_.size(); ++i) {
    if (frames_[i].timestamp_ns < frames_[i - 1].timestamp_ns) {
      *error = options.path + ": timestamps go backwards at frame " + std::to_string(i + 1);
      return false;
    }
  }
  next_ = 0;
  tracker_.on_interface_up();
  return true;
}

bool CandumpReplaySource::set_filters(std::span<const FrameId> ids, std::string*) {
  filters_.assign(ids.begin(), ids.end());
  return true;
}

bool CandumpReplaySource::passes_filter(const CanFrame& frame) const {
  if (frame.kind == FrameKind::kError || filters_.empty()) return true;
  return std::find(filters_.begin(), filters_.end(), FrameId{frame.id, frame.extended}) != filters_.end();
}

size_t CandumpReplaySource::drain(std::span<CanFrame> out, uint64_t now_ns) {
  size_t n = 0;
  while (n < out.size() && next_ < frames_.size() && frames_[next_].timestamp_ns <= now_ns) {
    const CanFrame& frame = frames_[next_++];
    if (!passes_filter(frame)) {
      ++tracker_.counters().foreign_frames;
      continue;
    }
    if (frame.kind == FrameKind::kError) {
      tracker_.on_error_frame(frame);
    } else {
      tracker_.on_frame_received();
    }
    out[n++] = frame;
  }
  return n;
}

}  // namespace sinew::hal::can
