// The tick's worker threads: sim_core's layer::Workers (sim_core/layer/workers.hpp)
// over threads created once at start-up. A loop is cut into
// kRangesPerThread ranges per thread, fixed by the loop's length alone;
// the tick thread and `threads - 1` workers claim them in turn (an atomic
// counter), so a thread that finishes early takes more (the costly
// vertices of a mesh are not spread evenly). Which range runs on which
// thread changes nothing in the output (each range writes its own elements).
//
// Waiting: between steps a worker sleeps on a futex (std::atomic wait) and
// costs no CPU. Waking a sleeping thread on another core can take longer
// than a loop (77 us median, 230 us at p99 between two idle vCPUs of this
// project's CI machine), so a step that uses the workers wakes them once
// at its start (begin_step) and they spin on the next loop until its end
// (end_step). A loop allocates nothing.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "sim_core/layer/workers.hpp"

namespace sinew::firmware {

class WorkerPool {
 public:
  WorkerPool() = default;
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;
  ~WorkerPool() { stop(); }

  // threads: 1..layer::kMaxParts, the calling (tick) thread included; 1
  // starts none. fifo_priority (0: default policy) and first_cpu (-1: no
  // affinity; worker i is pinned to CPU first_cpu + i - 1) are applied to
  // each worker as apply_thread_realtime does, and `report` gets its lines
  // saying what took effect. Returns false with `error` when a thread
  // cannot start.
  bool start(uint32_t threads, int fifo_priority, int first_cpu, std::string* report, std::string* error);
  void stop();

  // What the pipeline is given (PipelineOptions::workers). Valid while the
  // pool lives.
  const layer::Workers* workers() const { return &workers_; }
  uint32_t threads() const { return threads_count_; }

  static constexpr uint32_t kRangesPerThread = 8;

 private:
  static void run(void* pool, layer::RangeJob job, void* context, uint32_t count);
  static void begin_step(void* pool);
  static void end_step(void* pool);
  void worker_loop(uint32_t seen_job, uint32_t seen_wake);
  void claim_ranges();

  layer::Workers workers_;
  uint32_t threads_count_ = 1;
  std::vector<std::thread> threads_;
  // One loop at a time: published by bumping job_generation_ (then
  // wake_generation_, which sleeping workers wait on), finished when
  // pending_ reaches 0. stepping_: workers spin instead of sleeping.
  layer::RangeJob job_ = nullptr;
  void* context_ = nullptr;
  uint32_t count_ = 0;
  std::atomic<uint32_t> job_generation_{0};
  std::atomic<uint32_t> wake_generation_{0};
  std::atomic<bool> stepping_{false};
  std::atomic<uint32_t> next_range_{0};
  std::atomic<uint32_t> pending_{0};
  std::atomic<bool> stopping_{false};
};

}  // namespace sinew::firmware
