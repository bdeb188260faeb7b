#include "simulated_can_bus.hpp"

#include <algorithm>

namespace sinew::hal::can {

SimulatedCanBus::SimulatedCanBus(size_t capacity, BackoffPolicy backoff)
    : ring_(capacity == 0 ? 1 : capacity), backoff_(backoff) {
  tracker_.on_interface_up();  // opened at construction, as SocketCanSource::open() at configuration
}

bool SimulatedCanBus::set_filters(std::span<const FrameId> ids, std::string* /*error*/) {
  filters_.assign(ids.begin(), ids.end());
  return true;
}

bool SimulatedCanBus::passes_filter(const CanFrame& frame) const {
  if (frame.kind == FrameKind::kError || filters_.empty()) return true;
  return std::find(filters_.begin(), filters_.end(), FrameId{frame.id, frame.extended}) != filters_.end();
}

bool SimulatedCanBus::push(const CanFrame& frame) {
  if (!interface_up_) return false;
  if (count_ == ring_.size()) {
    ++tracker_.counters().dropped;  // the kernel drops the newest frame when the queue is full
    return false;
  }
  ring_[(head_ + count_) % ring_.size()] = frame;
  ++count_;
  return true;
}

bool SimulatedCanBus::inject(const CanFrame& frame) {
  if (frame.kind != FrameKind::kError && controller_bus_off_) return false;
  if (!passes_filter(frame)) {
    ++tracker_.counters().foreign_frames;
    return false;
  }
  return push(frame);
}

void SimulatedCanBus::bus_off(uint64_t timestamp_ns) {
  controller_bus_off_ = true;
  push(make_bus_off_error_frame(timestamp_ns));
}

void SimulatedCanBus::restart(uint64_t timestamp_ns) {
  controller_bus_off_ = false;
  push(make_restarted_error_frame(timestamp_ns));
}

void SimulatedCanBus::controller_state(BusState state, uint64_t timestamp_ns) {
  push(make_controller_state_error_frame(state, timestamp_ns));
}

void SimulatedCanBus::set_interface_up(bool up) {
  if (!up && interface_up_) {
    down_reported_ = open_;
    head_ = 0;
    count_ = 0;  // a downed interface loses what was queued
  }
  interface_up_ = up;
}

size_t SimulatedCanBus::drain(std::span<CanFrame> out, uint64_t now_ns) {
  if (down_reported_) {
    // What recvmsg reports after the interface went down: ENETDOWN. The
    // backend closes its socket and reopens with back-off.
    down_reported_ = false;
    open_ = false;
    tracker_.on_interface_down();
    backoff_.failed(now_ns);
    return 0;
  }
  if (!open_) {
    if (!backoff_.due(now_ns)) return 0;
    ++tracker_.counters().reopen_attempts;
    if (!interface_up_) {
      tracker_.on_interface_down();
      backoff_.failed(now_ns);
      return 0;
    }
    open_ = true;
    backoff_.succeeded();
    ++tracker_.counters().reopens;
    tracker_.on_interface_up();
  }
  size_t n = 0;
  while (n < out.size() && count_ > 0) {
    const CanFrame& f = ring_[head_];
    if (f.kind == FrameKind::kError) {
      tracker_.on_error_frame(f);
    } else {
      tracker_.on_frame_received();
    }
    out[n++] = f;
    head_ = (head_ + 1) % ring_.size();
    --count_;
  }
  return n;
}

}  // namespace sinew::hal::can
