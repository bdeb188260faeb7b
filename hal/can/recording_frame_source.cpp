#include "recording_frame_source.hpp"

namespace sinew::hal::can {

std::unique_ptr<RecordingFrameSource> RecordingFrameSource::create(std::unique_ptr<FrameSource> inner,
                                                                   const std::string& path, std::string interface,
                                                                   uint64_t origin_ns, std::string* error) {
  std::unique_ptr<RecordingFrameSource> s(new RecordingFrameSource());
  if (!s->writer_.open(path, error)) return nullptr;
  s->inner_ = std::move(inner);
  s->interface_ = std::move(interface);
  s->origin_ns_ = origin_ns;
  return s;
}

size_t RecordingFrameSource::drain(std::span<CanFrame> out, uint64_t now_ns) {
  const size_t n = inner_->drain(out, now_ns);
  for (size_t i = 0; i < n; ++i) {
    CanFrame logged = out[i];
    const uint64_t t = logged.timestamp_ns > origin_ns_ ? logged.timestamp_ns - origin_ns_ : 0;
    logged.timestamp_ns = (t + 999u) / 1000u * 1000u;  // ceiling to 1 us
    writer_.write(logged, interface_);
  }
  return n;
}

}  // namespace sinew::hal::can
