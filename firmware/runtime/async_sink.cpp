#include "async_sink.hpp"

#include <time.h>

#include "realtime.hpp"

namespace sinew::firmware {

namespace {

uint64_t io_thread_now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1'000'000'000u + static_cast<uint64_t>(ts.tv_nsec);
}

// How stale the wrapped sink's line in status_line() may get while frames
// flow: the daemon's statistics read it every few seconds.
constexpr uint64_t kStatusRefreshNs = 250'000'000;

}  // namespace

AsyncSink::AsyncSink(std::unique_ptr<OutputSink> inner, const FrameDims& dims, const AsyncSinkOptions& options,
                     std::string* report)
    : inner_(std::move(inner)), options_(options) {
  ring_.init(options.ring_frames, dims);
  status_ = inner_->status_line();
  thread_ = std::thread([this] { run(); });
  const std::string label = std::string("sink ") + inner_->name() + " I/O thread";
  *report = apply_thread_realtime(thread_.native_handle(), options.fifo_priority, options.cpu, label);
}

// The producer and consumer each publish "I am about to sleep" and then
// re-check the other side's counter, all seq_cst (Dekker): either the waker
// sees the flag, or the sleeper sees the new count. No wake-up is lost.
bool AsyncSink::write(const hal::PoseFrame& frame) {
  while (!ring_.try_push(frame)) {
    if (!options_.lossless || stopping_.load()) {
      ring_drops_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    const uint64_t tail = ring_.tail().load();
    producer_waiting_.store(true);
    if (ring_.size() >= ring_.capacity() && ring_.tail().load() == tail) ring_.tail().wait(tail);
    producer_waiting_.store(false);
  }
  const size_t queued = ring_.size();
  if (queued > high_water_.load(std::memory_order_relaxed)) high_water_.store(queued, std::memory_order_relaxed);
  if (consumer_sleeping_.load()) wake();
  return true;
}

void AsyncSink::wake() {
  wake_count_.fetch_add(1);
  wake_count_.notify_one();
}

void AsyncSink::flush() {
  flush_requested_.store(true);
  wake();
}

void AsyncSink::run() {
  uint64_t refreshed_ns = io_thread_now_ns();
  for (;;) {
    bool wrote = false;
    while (const hal::PoseFrame* frame = ring_.front()) {
      if (!inner_->write(*frame)) sink_drops_.fetch_add(1, std::memory_order_relaxed);
      ring_.pop();
      wrote = true;
      if (producer_waiting_.load()) ring_.tail().notify_one();
    }
    if (wrote && io_thread_now_ns() - refreshed_ns >= kStatusRefreshNs) {
      refresh_status();
      refreshed_ns = io_thread_now_ns();
    }
    if (flush_requested_.exchange(false)) {
      inner_->flush();
      refresh_status();
    }
    if (stopping_.load() && ring_.empty()) break;
    if (options_.poll_ns > 0) {
      // Polled: nobody wakes this thread for a frame; stop and flush are
      // seen at the next poll.
      const timespec pause{static_cast<time_t>(options_.poll_ns / 1'000'000'000u),
                           static_cast<long>(options_.poll_ns % 1'000'000'000u)};
      while (clock_nanosleep(CLOCK_MONOTONIC, 0, &pause, nullptr) == EINTR) {
      }
      continue;
    }
    const uint32_t seen = wake_count_.load();
    consumer_sleeping_.store(true);
    if (ring_.empty() && !flush_requested_.load() && !stopping_.load()) wake_count_.wait(seen);
    consumer_sleeping_.store(false);
  }
  inner_->flush();
  refresh_status();
}

void AsyncSink::refresh_status() {
  std::string line = inner_->status_line();
  const std::lock_guard<std::mutex> lock(status_mutex_);
  status_ = std::move(line);
}

std::string AsyncSink::status_line() const {
  std::string line;
  {
    const std::lock_guard<std::mutex> lock(status_mutex_);
    line = status_;
  }
  return line + "; ring " + std::to_string(ring_.capacity()) + " frames, most queued " +
         std::to_string(ring_high_water()) + ", dropped when full " + std::to_string(ring_drops());
}

void AsyncSink::stop() {
  if (!thread_.joinable()) return;
  stopping_.store(true);
  wake();
  thread_.join();
}

}  // namespace sinew::firmware
