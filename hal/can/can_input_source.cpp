#include "can_input_source.hpp"

#include <algorithm>

namespace sinew::hal::can {

std::unique_ptr<CanInputSource> CanInputSource::create(std::string name, std::unique_ptr<FrameSource> source,
                                                       std::unique_ptr<FrameDecoder> decoder, size_t frame_capacity,
                                                       uint64_t start_ns, std::string* error,
                                                       const SyncFrameOptions& sync) {
  std::unique_ptr<CanInputSource> s(new CanInputSource());
  s->name_ = std::move(name);
  s->source_ = std::move(source);
  s->decoder_ = std::move(decoder);
  if (!s->receiver_.configure(*s->source_, *s->decoder_, frame_capacity, start_ns, error, sync)) return nullptr;
  return s;
}

size_t CanInputSource::latch(uint64_t until_ns, std::span<JointSample> out, InputHealth& health) {
  // Which frames belong to this tick is decided by their timestamps alone, so
  // live, replay and offline runs agree. The tick time also paces the source's
  // reopen back-off (in live mode it is the real clock, to within a tick).
  const PollResult r = receiver_.poll(until_ns, until_ns);
  for (const Rejection& rej : r.rejections) health.reject(rej.input, rej.reason);
  // create() sizes the receiver so that a tick's samples always fit; were
  // `out` smaller, the newest samples (which supersede older ones) are kept.
  const size_t n = std::min(out.size(), r.samples.size());
  std::copy(r.samples.end() - static_cast<std::ptrdiff_t>(n), r.samples.end(), out.begin());
  return n;
}

uint8_t CanInputSource::arrival_signals() const {
  return static_cast<uint8_t>(kSignalsComplete | (receiver_.has_sync() ? kSignalsSync : kSignalsNothing));
}

Arrival CanInputSource::arrival(uint64_t now_ns) {
  const ArrivalState a = receiver_.arrival(now_ns);
  return {a.complete, a.sync};
}

SourceState CanInputSource::state() const {
  switch (receiver_.bus_state()) {
    case BusState::kErrorActive:
      return SourceState::kOk;
    case BusState::kErrorWarning:
    case BusState::kErrorPassive:
      return SourceState::kDegraded;
    case BusState::kBusOff:
    case BusState::kInterfaceDown:
      return SourceState::kDown;
  }
  return SourceState::kDown;
}

std::string CanInputSource::status_line() const {
  const BusCounters& c = receiver_.bus_counters();
  return std::string(source_->name()) + " " + bus_state_name(receiver_.bus_state()) + ", frames " +
         std::to_string(c.frames) + ", error frames " + std::to_string(c.error_frames) + ", bus-off " +
         std::to_string(c.bus_off_events) + ", dropped " + std::to_string(c.dropped) + ", foreign " +
         std::to_string(c.foreign_frames) +
         (receiver_.has_sync() ? ", sync frames " + std::to_string(receiver_.sync_frames()) : std::string()) +
         // "ok, frames 0" alone would hide a log or bus of another device's frames.
         (c.frames == 0 && c.foreign_frames > 0 ? " (every frame had identifiers this decoder does not read)" : "");
}

}  // namespace sinew::hal::can
