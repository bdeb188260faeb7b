// Workers for tests (sim_core/layer/workers.hpp): every loop's ranges run on
// threads started for that loop, assigned in reverse (thread 0 takes the
// last range) and started in that order, so a stage whose output depended
// on which range runs first, or on which thread, would differ from the
// serial run. Allocates per loop: for tests of determinism, not of the tick.
#pragma once

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
  }
  const layer::Workers* workers() const { return &workers_; }
  uint32_t loops() const { return loops_; }

 private:
  static void run(void* pool, layer::RangeJob job, void* context, uint32_t count) {
    auto& self = *static_cast<ThreadPerRangeWorkers*>(pool);
    const uint32_t parts = self.workers_.parts;
    std::vector<std::thread> threads;
    for (uint32_t k = 0; k < parts; ++k) {
      const uint32_t i = parts - 1 - k;
      threads.emplace_back(
          [=] { job(context, layer::range_begin(count, parts, i), layer::range_begin(count, parts, i + 1)); });
    }
    for (std::thread& t : threads) t.join();
    ++self.loops_;
  }

  layer::Workers workers_;
  uint32_t loops_ = 0;
};

}  // namespace sinew::test
