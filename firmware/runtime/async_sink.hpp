// Takes a sink off the tick thread. write() copies the frame into a ring of
// slots allocated at start (FrameRing) and returns; one I/O thread per sink
// hands the frames, in order, to the wrapped sink, whose file writes, sends
// and fdatasync() stall only that thread. A slow sink cannot delay the tick
// or another sink.
//
// A full ring either drops the frame (live runs: the tick never waits;
// counted, reported, and the exit status says the output is incomplete) or,
// with `lossless`, makes write() wait for a free slot (offline and replay
// runs, which have no deadline and must not lose frames).
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "frame_ring.hpp"
#include "io.hpp"

namespace sinew::firmware {

struct AsyncSinkOptions {
  size_t ring_frames = 128;  // slots; at 1 kHz, 128 ms of frames
  bool lossless = false;     // wait for a slot instead of dropping
  int fifo_priority = 0;     // the I/O thread's SCHED_FIFO priority; 0: default policy
  int cpu = -1;              // pin the I/O thread to this CPU; -1: no affinity
  // 0: the tick wakes the I/O thread for each frame (one futex wake and, on
  // another CPU, an inter-processor interrupt per frame). > 0: the I/O thread
  // wakes on its own every poll_ns and drains what is queued, so the tick
  // makes no system call at all; a frame leaves up to poll_ns later. Keep it
  // well below the ring's duration (ring_frames periods).
  uint64_t poll_ns = 0;
};

class AsyncSink final : public OutputSink {
 public:
  // Sizes the ring for `dims` and starts the I/O thread. `report` gets one
  // line per realtime option saying whether it took effect.
  AsyncSink(std::unique_ptr<OutputSink> inner, const FrameDims& dims, const AsyncSinkOptions& options,
            std::string* report);
  ~AsyncSink() override { stop(); }
  AsyncSink(const AsyncSink&) = delete;
  AsyncSink& operator=(const AsyncSink&) = delete;

  const char* name() const override { return inner_->name(); }
  // Tick thread: one copy into the ring, no lock, no allocation, no system
  // call unless the I/O thread sleeps on a wake-up (one futex wake; never
  // with poll_ns > 0). False: dropped.
  bool write(const hal::PoseFrame& frame) override;
  // Asks the I/O thread to flush the wrapped sink; returns at once.
  void flush() override;
  // The wrapped sink's line as of the I/O thread's last flush, plus the ring's counters.
  std::string status_line() const override;

  // Writes what is queued, flushes, and ends the I/O thread. Idempotent.
  void close() override { stop(); }
  void stop();
  uint64_t frames_lost_after_write() const override { return sink_drops(); }

  uint64_t ring_drops() const { return ring_drops_.load(std::memory_order_relaxed); }
  uint64_t sink_drops() const { return sink_drops_.load(std::memory_order_relaxed); }
  size_t ring_high_water() const { return high_water_.load(std::memory_order_relaxed); }
  // Wake-ups sent to the I/O thread (frames, flushes, the stop).
  uint32_t wakes() const { return wake_count_.load(std::memory_order_relaxed); }

 private:
  void run();
  void wake();
  void refresh_status();

  std::unique_ptr<OutputSink> inner_;
  AsyncSinkOptions options_;
  FrameRing ring_;
  std::atomic<uint32_t> wake_count_{0};  // bumped to wake the I/O thread
  std::atomic<bool> consumer_sleeping_{false};
  std::atomic<bool> producer_waiting_{false};
  std::atomic<bool> flush_requested_{false};
  std::atomic<bool> stopping_{false};
  std::atomic<uint64_t> ring_drops_{0}, sink_drops_{0};
  std::atomic<size_t> high_water_{0};
  mutable std::mutex status_mutex_;  // held only to copy the status string
  std::string status_;
  std::thread thread_;
};

}  // namespace sinew::firmware
