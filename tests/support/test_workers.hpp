// Workers for tests (sim_core/layer/workers.hpp): every loop's ranges run on
// threads of their own, assigned in reverse (thread 0 takes the last range)
// and woken together for each loop, so a stage whose output depended on
// which range runs first, or on which thread, would differ from the serial
// run. The threads are started once (starting threads per loop made the
// determinism tests take minutes under qemu); a loop waits for all of them.
// For tests of determinism, not of the tick (the firmware's WorkerPool is
// the real-time one).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "sim_core/layer/workers.hpp"

namespace sinew::test {

class ThreadPerRangeWorkers {
 public:
  explicit ThreadPerRangeWorkers(uint32_t parts) {
    workers_.parts = parts;
    workers_.pool = this;
    workers_.run = &ThreadPerRangeWorkers::run;
    for (uint32_t k = 0; k < parts; ++k) threads_.emplace_back([this, k] { serve(k); });
  }
  ~ThreadPerRangeWorkers() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
      ++generation_;
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
  }
  ThreadPerRangeWorkers(const ThreadPerRangeWorkers&) = delete;
  ThreadPerRangeWorkers& operator=(const ThreadPerRangeWorkers&) = delete;

  const layer::Workers* workers() const { return &workers_; }
  uint32_t loops() const { return loops_; }

 private:
  static void run(void* pool, layer::RangeJob job, void* context, uint32_t count) {
    auto& self = *static_cast<ThreadPerRangeWorkers*>(pool);
    std::unique_lock<std::mutex> lock(self.mutex_);
    self.job_ = job;
    self.context_ = context;
    self.count_ = count;
    self.pending_ = self.workers_.parts;
    ++self.generation_;
    self.wake_.notify_all();
    self.done_.wait(lock, [&] { return self.pending_ == 0; });
    ++self.loops_;
  }

  // Thread k runs range parts - 1 - k of every loop.
  void serve(uint32_t k) {
    uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return generation_ != seen; });
      seen = generation_;
      if (stop_) return;
      const layer::RangeJob job = job_;
      void* const context = context_;
      const uint32_t count = count_, parts = workers_.parts, i = parts - 1 - k;
      lock.unlock();
      job(context, layer::range_begin(count, parts, i), layer::range_begin(count, parts, i + 1));
      lock.lock();
      if (--pending_ == 0) done_.notify_one();
    }
  }

  layer::Workers workers_;
  uint32_t loops_ = 0;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  uint64_t generation_ = 0;
  bool stop_ = false;
  layer::RangeJob job_ = nullptr;
  void* context_ = nullptr;
  uint32_t count_ = 0;
  uint32_t pending_ = 0;
  std::vector<std::thread> threads_;
};

}  // namespace sinew::test
