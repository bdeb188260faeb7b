#include "gpio_source.hpp"

#include <time.h>

#include <cstring>
#include <utility>

#include "libgpiod_chip.hpp"

namespace sinew::hal::gpio {

namespace {

// Bounds the work of one latch: each round reads at most event_capacity events.
constexpr int kMaxReadRounds = 4;
constexpr size_t kSyncBatch = 16;

uint64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1'000'000'000u + static_cast<uint64_t>(ts.tv_nsec);
}

bool logical(Edge edge, bool active_low) { return (edge == Edge::kRising) != active_low; }

}  // namespace

std::unique_ptr<GpioSource> GpioSource::create(GpioSourceConfig config, std::string* error) {
  if (!validate(config, 0, error)) return nullptr;
  std::unique_ptr<GpioChip> chip = open_libgpiod_chip(config.chip, config.consumer, error);
  if (!chip) return *error = "gpio source '" + config.name + "': " + *error, nullptr;
  return create(std::move(config), std::move(chip), error);
}

std::unique_ptr<GpioSource> GpioSource::create(GpioSourceConfig config, std::unique_ptr<GpioChip> chip,
                                               std::string* error) {
  if (!chip) return *error = "gpio source '" + config.name + "': no chip", nullptr;
  if (!validate(config, chip->line_count(), error)) return nullptr;
  std::unique_ptr<GpioSource> source(new GpioSource(std::move(config), std::move(chip)));
  if (!source->init(error)) return nullptr;
  return source;
}

GpioSource::GpioSource(GpioSourceConfig config, std::unique_ptr<GpioChip> chip)
    : config_(std::move(config)), chip_(std::move(chip)) {}

GpioSource::~GpioSource() {
  if (fault_) fault_->set_level(!config_.fault.active_low);  // leave the line saying "fault"
}

bool GpioSource::init(std::string* error) {
  const std::string prefix = "gpio source '" + config_.name + "': ";
  roles_.assign(chip_->line_count(), LineRole{});
  std::vector<uint32_t> offsets;
  for (uint32_t i = 0; i < config_.encoders.size(); ++i) {
    const EncoderConfig& e = config_.encoders[i];
    roles_[e.line_a] = {Role::kA, e.active_low, i};
    roles_[e.line_b] = {Role::kB, e.active_low, i};
    offsets.push_back(e.line_a);
    offsets.push_back(e.line_b);
    if (e.line_index != kNoLine) {
      roles_[static_cast<uint32_t>(e.line_index)] = {Role::kIndex, e.active_low, i};
      offsets.push_back(static_cast<uint32_t>(e.line_index));
    }
  }
  for (uint32_t i = 0; i < config_.limits.size(); ++i) {
    roles_[config_.limits[i].line] = {Role::kLimit, config_.limits[i].active_low, i};
    offsets.push_back(config_.limits[i].line);
  }
  std::vector<uint8_t> levels(offsets.size(), 0);
  if (!offsets.empty()) {
    inputs_ = chip_->request_inputs(offsets, error);
    if (!inputs_) return *error = prefix + *error, false;
    if (!inputs_->get_levels(levels))
      return *error = prefix + "reading the initial levels failed: " + std::strerror(inputs_->last_error()), false;
  }
  // Offsets were pushed in config order, so `levels` is walked the same way.
  size_t k = 0;
  encoders_.resize(config_.encoders.size());
  for (size_t i = 0; i < config_.encoders.size(); ++i) {
    const EncoderConfig& e = config_.encoders[i];
    const bool a = (levels[k++] != 0) != e.active_low;
    const bool b = (levels[k++] != 0) != e.active_low;
    if (e.line_index != kNoLine) ++k;
    encoders_[i].reset(a, b, e.window_ns);
  }
  limits_.resize(config_.limits.size());
  for (size_t i = 0; i < config_.limits.size(); ++i) {
    const LimitSwitchConfig& l = config_.limits[i];
    limits_[i].reset((levels[k++] != 0) != l.active_low, l.debounce_ns);
  }
  if (config_.sync.line != kNoLine) {
    const uint32_t line = static_cast<uint32_t>(config_.sync.line);
    sync_ = chip_->request_inputs(std::span<const uint32_t>(&line, 1), error);
    if (!sync_) return *error = prefix + "sync: " + *error, false;
  }
  if (config_.fault.line != kNoLine) {
    fault_ = chip_->request_output(static_cast<uint32_t>(config_.fault.line), !config_.fault.active_low, error);
    if (!fault_) return *error = prefix + "fault: " + *error, false;
  }
  levels_ = std::move(levels);
  pending_.resize(config_.event_capacity);
  sync_buffer_.resize(kSyncBatch);
  return true;
}

void GpioSource::apply(const LineEvent& event) {
  uint64_t ts = event.timestamp_ns;
  if (ts < last_ts_) {
    ++counters_.late_events;  // read after a newer one on another line: treat as simultaneous
    ts = last_ts_;
  }
  last_ts_ = ts;
  if (event.offset >= roles_.size()) return;
  const LineRole& r = roles_[event.offset];
  const bool level = logical(event.edge, r.active_low);
  ++counters_.events;
  switch (r.role) {
    case Role::kA:
      encoders_[r.index].on_edge(0, level, ts);
      break;
    case Role::kB:
      encoders_[r.index].on_edge(1, level, ts);
      break;
    case Role::kIndex:
      if (level) {
        const EncoderConfig& e = config_.encoders[r.index];
        encoders_[r.index].on_index(ts, e.invert ? -e.index_count : e.index_count, e.home_every_index);
      }
      break;
    case Role::kLimit:
      limits_[r.index].on_edge(level, ts);
      break;
    case Role::kNone:
      break;
  }
}

hal::Arrival GpioSource::arrival(uint64_t now_ns) {
  if (sync_ && !sync_pending_) {
    const int got = sync_->read_events(sync_buffer_);
    if (got < 0) ++counters_.read_errors;
    uint32_t active = 0;
    for (int i = 0; i < got; ++i) {
      const LineEvent& e = sync_buffer_[static_cast<size_t>(i)];
      if (!logical(e.edge, config_.sync.active_low)) continue;
      ++active;
      sync_pending_ns_ = e.timestamp_ns;  // the newest active edge, as wait_sync takes it
    }
    if (active > 0) {
      sync_pending_ = true;
      ++counters_.sync_edges;
      counters_.sync_missed += active - 1;
    }
  }
  return {false, sync_pending_ && sync_pending_ns_ <= now_ns};
}

size_t GpioSource::latch(uint64_t until_ns, std::span<hal::JointSample> out, hal::InputHealth&) {
  if (sync_pending_ && sync_pending_ns_ <= until_ns) sync_pending_ = false;  // this tick answers the edge
  bool read_failed = false;
  if (inputs_) {
    for (int round = 0; round < kMaxReadRounds; ++round) {
      if (head_ > 0) {  // keep the staged events at the front
        std::memmove(pending_.data(), pending_.data() + head_, (tail_ - head_) * sizeof(LineEvent));
        tail_ -= head_;
        head_ = 0;
      }
      const size_t space = pending_.size() - tail_;
      int got = 0;
      if (space > 0) {
        got = inputs_->read_events(std::span<LineEvent>(pending_.data() + tail_, space));
        if (got < 0) {
          ++counters_.read_errors;
          read_failed = true;
          break;
        }
        tail_ += static_cast<size_t>(got);
      }
      while (head_ < tail_ && pending_[head_].timestamp_ns <= until_ns) apply(pending_[head_++]);
      // Done when later events wait in the buffer or the backend had no more.
      if (head_ < tail_ || static_cast<size_t>(got) < space) break;
    }
  }
  // A full kernel FIFO may have dropped edges: once every staged event is
  // applied, the lines' levels now must match the decoded state.
  if (!read_failed && inputs_ && head_ == tail_ && inputs_->possible_overflows() != seen_overflows_) {
    seen_overflows_ = inputs_->possible_overflows();
    resync_levels(until_ns);
  }
  uint64_t problems = 0;
  for (QuadratureDecoder& d : encoders_) {
    d.settle(until_ns);
    problems += d.counters().illegal + d.counters().missed_edges + d.counters().resyncs;
  }
  for (Debouncer& l : limits_) l.settle(until_ns);
  state_ = read_failed                  ? hal::SourceState::kDown
           : problems != last_problems_ ? hal::SourceState::kDegraded
                                        : hal::SourceState::kOk;
  last_problems_ = problems;
  if (read_failed) return 0;

  size_t n = 0;
  for (size_t i = 0; i < encoders_.size() && n < out.size(); ++i) {
    const EncoderConfig& e = config_.encoders[i];
    if (e.line_index != kNoLine && !encoders_[i].homed()) continue;
    const int64_t count = e.invert ? -encoders_[i].count() : encoders_[i].count();
    out[n++] =
        hal::JointSample{e.input, counts_to_angle(count, e.counts_per_turn, e.offset), until_ns, limit_flags(e.input)};
  }
  return n;
}

void GpioSource::resync_levels(uint64_t now_ns) {
  ++counters_.overflow_checks;
  if (!inputs_->get_levels(levels_)) return;
  size_t k = 0;  // request order: per encoder A, B[, index], then the limits
  for (size_t i = 0; i < encoders_.size(); ++i) {
    const EncoderConfig& e = config_.encoders[i];
    const bool a = (levels_[k++] != 0) != e.active_low;
    const bool b = (levels_[k++] != 0) != e.active_low;
    if (e.line_index != kNoLine) ++k;
    encoders_[i].resync(a, b);
  }
  for (size_t i = 0; i < limits_.size(); ++i)
    limits_[i].on_edge((levels_[k++] != 0) != config_.limits[i].active_low, now_ns);
}

uint8_t GpioSource::limit_flags(uint16_t input) const {
  uint8_t flags = 0;
  for (size_t i = 0; i < limits_.size(); ++i) {
    const LimitSwitchConfig& l = config_.limits[i];
    if (l.input == input && limits_[i].stable())
      flags |= l.side == LimitSide::kMin ? kSampleAtMinLimit : kSampleAtMaxLimit;
  }
  return flags;
}

SyncEdge GpioSource::wait_sync(uint64_t timeout_ns) {
  SyncEdge result;
  if (!sync_) return result.result = WaitResult::kError, result;
  const uint64_t deadline = monotonic_ns() + timeout_ns;
  for (;;) {
    const int got = sync_->read_events(sync_buffer_);
    if (got < 0) {
      ++counters_.read_errors;
      return result.result = WaitResult::kError, result;
    }
    uint32_t active = 0;
    for (int i = 0; i < got; ++i) {
      const LineEvent& e = sync_buffer_[static_cast<size_t>(i)];
      if (!logical(e.edge, config_.sync.active_low)) continue;
      ++active;
      result.timestamp_ns = e.timestamp_ns;
    }
    if (active > 0) {
      // The newest active edge starts this tick; older ones were ticks we did not follow.
      result.result = WaitResult::kReady;
      result.missed = active - 1;
      ++counters_.sync_edges;
      counters_.sync_missed += result.missed;
      return result;
    }
    if (static_cast<size_t>(got) == sync_buffer_.size()) continue;  // more queued
    const uint64_t now = monotonic_ns();
    const WaitResult w = sync_->wait(deadline > now ? deadline - now : 0);
    if (w == WaitResult::kError) {
      ++counters_.read_errors;
      return result.result = WaitResult::kError, result;
    }
    if (w == WaitResult::kTimeout || monotonic_ns() > deadline) {
      ++counters_.sync_timeouts;
      return result.result = WaitResult::kTimeout, result;
    }
  }
}

bool GpioSource::set_fault(bool fault) {
  if (!fault_) return false;
  return fault_->set_level(fault != config_.fault.active_low);
}

std::string GpioSource::status_line() const {
  std::string s = std::string(hal::source_state_name(state_)) + ", " + std::to_string(encoders_.size()) + " encoders";
  for (size_t i = 0; i < encoders_.size(); ++i) {
    const QuadratureCounters& c = encoders_[i].counters();
    s += " [" + std::to_string(i) + ": count " + std::to_string(encoders_[i].count()) +
         (config_.encoders[i].line_index != kNoLine && !encoders_[i].homed() ? " not homed" : "") + ", illegal " +
         std::to_string(c.illegal) + ", missed " + std::to_string(c.missed_edges) + ", resyncs " +
         std::to_string(c.resyncs) + "]";
  }
  for (size_t i = 0; i < limits_.size(); ++i)
    s += " limit" + std::to_string(i) + (limits_[i].stable() ? " pressed" : " free");
  s += ", events " + std::to_string(counters_.events) + ", read errors " + std::to_string(counters_.read_errors);
  if (sync_)
    s += ", sync " + std::to_string(counters_.sync_edges) + " (missed " + std::to_string(counters_.sync_missed) +
         ", timeouts " + std::to_string(counters_.sync_timeouts) + ")";
  return s;
}

}  // namespace sinew::hal::gpio
