#include "worker_pool.hpp"

#include <algorithm>
#include <system_error>

#include "realtime.hpp"

namespace sinew::firmware {
namespace {

// A spinning thread's pause: lets the core's sibling and the memory system
// breathe (x86 PAUSE, Arm YIELD).
inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__) || defined(__arm__)
  asm volatile("yield");
#endif
}

// Pauses the tick thread spins on a loop's last ranges before it sleeps:
// tens of microseconds.
constexpr uint32_t kSpinBeforeSleep = 4096;

}  // namespace

bool WorkerPool::start(uint32_t threads, int fifo_priority, int first_cpu, std::string* report, std::string* error) {
  stop();
  if (threads < 1 || threads > layer::kMaxParts) {
    *error = "[realtime] workers = " + std::to_string(threads) + ": must be 1.." + std::to_string(layer::kMaxParts);
    return false;
  }
  stopping_.store(false);
  workers_ = {};
  threads_count_ = threads;
  if (threads == 1) return true;  // the tick thread alone: no pool
  threads_.reserve(threads - 1);
  // The generation the workers start from, read before any starts: a loop
  // published before a worker first runs is then still new to it.
  const uint32_t start_job = job_generation_.load(std::memory_order_acquire);
  const uint32_t start_wake = wake_generation_.load(std::memory_order_acquire);
  for (uint32_t part = 1; part < threads; ++part) {
    try {
      threads_.emplace_back([this, start_job, start_wake] { worker_loop(start_job, start_wake); });
    } catch (const std::system_error& e) {
      *error = "[realtime] workers: cannot start worker " + std::to_string(part) + ": " + e.what();
      stop();
      return false;
    }
    const int cpu = first_cpu < 0 ? -1 : first_cpu + static_cast<int>(part) - 1;
    const std::string lines =
        apply_thread_realtime(threads_.back().native_handle(), fifo_priority, cpu, "worker " + std::to_string(part));
    if (report != nullptr) *report += lines;
  }
  workers_.run = &WorkerPool::run;
  workers_.begin_step = &WorkerPool::begin_step;
  workers_.end_step = &WorkerPool::end_step;
  workers_.pool = this;
  workers_.parts = std::min(threads * kRangesPerThread, layer::kMaxParts);
  return true;
}

void WorkerPool::stop() {
  if (threads_.empty()) return;
  stopping_.store(true);
  stepping_.store(false);
  wake_generation_.fetch_add(1, std::memory_order_release);
  wake_generation_.notify_all();
  for (std::thread& t : threads_) t.join();
  threads_.clear();
  workers_ = {};
  threads_count_ = 1;
}

void WorkerPool::claim_ranges() {
  const uint32_t parts = workers_.parts;
  for (uint32_t i = next_range_.fetch_add(1, std::memory_order_relaxed); i < parts;
       i = next_range_.fetch_add(1, std::memory_order_relaxed))
    job_(context_, layer::range_begin(count_, parts, i), layer::range_begin(count_, parts, i + 1));
}

void WorkerPool::begin_step(void* pool) {
  WorkerPool& p = *static_cast<WorkerPool*>(pool);
  if (p.stepping_.exchange(true)) return;
  p.wake_generation_.fetch_add(1, std::memory_order_release);
  p.wake_generation_.notify_all();
}

void WorkerPool::end_step(void* pool) { static_cast<WorkerPool*>(pool)->stepping_.store(false); }

void WorkerPool::run(void* pool, layer::RangeJob job, void* context, uint32_t count) {
  WorkerPool& p = *static_cast<WorkerPool*>(pool);
  p.job_ = job;
  p.context_ = context;
  p.count_ = count;
  p.next_range_.store(0, std::memory_order_relaxed);
  p.pending_.store(p.threads_count_ - 1, std::memory_order_relaxed);
  // Release: a worker that sees the new generation sees the job above.
  p.job_generation_.fetch_add(1, std::memory_order_release);
  p.wake_generation_.fetch_add(1, std::memory_order_release);
  if (!p.stepping_.load(std::memory_order_relaxed)) p.wake_generation_.notify_all();
  p.claim_ranges();
  // Acquire: every range's writes are visible once pending_ is 0. The
  // workers are finishing their last ranges: spin a while before sleeping
  // (a futex wake of this thread costs as much as waking a worker).
  for (uint32_t spin = 0; spin < kSpinBeforeSleep && p.pending_.load(std::memory_order_acquire) != 0; ++spin)
    cpu_relax();
  for (uint32_t left = p.pending_.load(std::memory_order_acquire); left != 0;
       left = p.pending_.load(std::memory_order_acquire))
    p.pending_.wait(left, std::memory_order_acquire);
}

void WorkerPool::worker_loop(uint32_t seen_job, uint32_t seen_wake) {
  for (;;) {
    uint32_t job = job_generation_.load(std::memory_order_acquire);
    while (job == seen_job) {
      if (stopping_.load(std::memory_order_relaxed)) return;
      if (stepping_.load(std::memory_order_relaxed)) {
        cpu_relax();
      } else {
        // Returns at once if a wake came since seen_wake; every new loop
        // bumps wake_generation_ after job_generation_.
        wake_generation_.wait(seen_wake, std::memory_order_acquire);
        seen_wake = wake_generation_.load(std::memory_order_acquire);
      }
      job = job_generation_.load(std::memory_order_acquire);
    }
    seen_job = job;
    if (stopping_.load()) return;
    claim_ranges();
    if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) pending_.notify_one();
  }
}

}  // namespace sinew::firmware
