#include "poller.hpp"

#include <pthread.h>
#include <sched.h>

#include <array>
#include <chrono>
#include <utility>

#include "hal/common/monotonic_clock.hpp"
#include "modbus_link.hpp"

namespace sinew::hal::modbus {

namespace {

PollSnapshot sized_snapshot(size_t channels) {
  PollSnapshot s;
  s.channels.assign(channels, ChannelSlot{});
  return s;
}

// The poller must not compete with the tick: if it was created by an already
// real-time thread it would inherit SCHED_FIFO, so it drops back explicitly.
void become_background_thread() {
  sched_param param{};
  param.sched_priority = 0;
  pthread_setschedparam(pthread_self(), SCHED_OTHER, &param);
  pthread_setname_np(pthread_self(), "sinew-modbus");
}

}  // namespace

Poller::Poller(PollerConfig config)
    : config_(std::move(config)),
      plan_(plan_requests(config_.channels, config_.max_registers_per_read, config_.max_gap)),
      work_(sized_snapshot(config_.channels.size())),
      exchange_(work_),
      backoff_(config_.backoff_initial_ns, config_.backoff_max_ns) {}

Poller::~Poller() { stop(); }

bool Poller::start(std::string* error) {
  if (thread_.joinable()) return true;
  link_ = std::make_unique<ModbusLink>(config_.link, config_.response_timeout_ns, config_.byte_timeout_ns);
  if (!link_->ok()) return *error = "modbus source '" + config_.name + "': " + link_->error(), false;
  stopping_.store(false);
  thread_ = std::thread([this] { run(); });
  return true;
}

void Poller::stop() {
  {
    std::lock_guard<std::mutex> lock(wake_mutex_);
    stopping_.store(true);
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

bool Poller::sleep_for(uint64_t ns) {
  std::unique_lock<std::mutex> lock(wake_mutex_);
  wake_.wait_for(lock, std::chrono::nanoseconds(ns), [this] { return stopping_.load(); });
  return !stopping_.load();
}

void Poller::publish() {
  exchange_.back() = work_;  // same sizes: reuses the copy's storage
  exchange_.publish();
}

void Poller::run() {
  become_background_thread();
  uint64_t next_cycle_ns = monotonic_ns();
  while (!stopping_.load()) {
    if (!link_->connected()) {
      if (!link_->connect()) {
        PollerStats::add(stats_.connect_failures);
        stats_.set_state(SourceState::kDown);
        mark_unanswered(0);
        publish();
        stats_.backoff_ns.store(backoff_.next());
        if (!sleep_for(backoff_.current())) break;
        continue;
      }
      PollerStats::add(stats_.connects);
    }

    const CycleResult cycle = poll_cycle();
    ++work_.cycle;
    PollerStats::add(stats_.cycles);
    publish();
    if (cycle.link_lost) link_->close();

    if (cycle.with_data == plan_.size()) {
      stats_.set_state(SourceState::kOk);
    } else {
      stats_.set_state(cycle.answered > 0 ? SourceState::kDegraded : SourceState::kDown);
    }

    if (cycle.with_data == 0) {
      // Nothing usable came back: wait longer each time instead of hammering.
      stats_.backoff_ns.store(backoff_.next());
      if (!sleep_for(backoff_.current())) break;
      next_cycle_ns = monotonic_ns();
      continue;
    }
    backoff_.reset();
    stats_.backoff_ns.store(0);
    // Fixed-rate cycles; after an overrun start the next one at once, without bursting.
    next_cycle_ns += config_.period_ns;
    const uint64_t now = monotonic_ns();
    if (next_cycle_ns <= now) {
      next_cycle_ns = now;
    } else if (!sleep_for(next_cycle_ns - now)) {
      break;
    }
  }
  link_->close();
}

Poller::CycleResult Poller::poll_cycle() {
  CycleResult result;
  std::array<uint16_t, kMaxReadRegisters> regs{};
  for (size_t r = 0; r < plan_.size(); ++r) {
    if (stopping_.load()) {
      mark_unanswered(r);
      break;
    }
    const ReadRequest& request = plan_[r];
    PollerStats::add(stats_.requests);
    const ReadResult read = link_->read(request.table, request.address, std::span(regs.data(), request.count));
    if (read.outcome == ReadOutcome::kOk) {
      accept_registers(request, std::span<const uint16_t>(regs.data(), request.count), monotonic_ns());
      ++result.with_data;
      ++result.answered;
      continue;
    }
    record_failure(request, read);
    if (read.outcome == ReadOutcome::kException) {
      ++result.answered;  // the link is fine; the device refused this block
      continue;
    }
    // Timeout, garbage or lost link. On TCP a late or stray response would
    // desynchronise the stream: reconnect. On a serial line, drop what is
    // pending; after a timeout the device is most likely gone, so end the cycle.
    const bool tcp = link_->transport() == Transport::kTcp;
    if (tcp || read.outcome == ReadOutcome::kLinkLost) {
      result.link_lost = true;
    } else {
      link_->flush();
    }
    if (result.link_lost || read.outcome == ReadOutcome::kTimeout) {
      mark_unanswered(r + 1);
      break;
    }
  }
  return result;
}

void Poller::accept_registers(const ReadRequest& request, std::span<const uint16_t> regs, uint64_t now_ns) {
  PollerStats::add(stats_.responses);
  for (uint16_t index : request.channels) {
    const ChannelConfig& c = config_.channels[index];
    ChannelSlot& slot = work_.channels[index];
    const Conversion conv =
        convert(c, regs.subspan(static_cast<size_t>(c.address - request.address), register_count(c.width)));
    if (!conv.accepted) {
      ++slot.out_of_range;
      slot.status = ChannelStatus::kOutOfRange;
      PollerStats::add(stats_.out_of_range);
      continue;
    }
    slot.value = conv.value;
    slot.timestamp_ns = now_ns;
    ++slot.samples;
    slot.status = ChannelStatus::kOk;
  }
}

void Poller::record_failure(const ReadRequest& request, const ReadResult& result) {
  switch (result.outcome) {
    case ReadOutcome::kException:
      PollerStats::add(stats_.exceptions);
      PollerStats::add(stats_.by_exception[result.exception_code < kExceptionCodes ? result.exception_code : 0]);
      break;
    case ReadOutcome::kTimeout:
      PollerStats::add(stats_.timeouts);
      break;
    case ReadOutcome::kBadResponse:
      PollerStats::add(stats_.bad_responses);
      break;
    case ReadOutcome::kLinkLost:
      PollerStats::add(stats_.link_errors);
      break;
    case ReadOutcome::kOk:
      break;
  }
  for (uint16_t index : request.channels) {
    ChannelSlot& slot = work_.channels[index];
    if (result.outcome == ReadOutcome::kException) {
      ++slot.exceptions;
      slot.last_exception = result.exception_code;
      slot.status = ChannelStatus::kException;
    } else {
      ++slot.failed_reads;
      slot.status = ChannelStatus::kNoResponse;
    }
  }
}

void Poller::mark_unanswered(size_t first_request) {
  for (size_t r = first_request; r < plan_.size(); ++r)
    for (uint16_t index : plan_[r].channels) work_.channels[index].status = ChannelStatus::kNoResponse;
}

}  // namespace sinew::hal::modbus
