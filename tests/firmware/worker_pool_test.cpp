// The tick's worker pool (firmware/runtime/worker_pool.hpp): every element
// of a loop is run exactly once for any worker count, a loop allocates
// nothing, and the pool refuses a count it cannot honour.
#include "firmware/runtime/worker_pool.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include "tests/support/alloc_guard.hpp"

namespace worker_pool_test {

struct Visits {
  std::vector<uint32_t> count;  // one slot per element; each range writes its own
};

void visit(void* context, uint32_t begin, uint32_t end) {
  auto& v = *static_cast<Visits*>(context);
  for (uint32_t i = begin; i < end; ++i) ++v.count[i];
}

}  // namespace worker_pool_test

TEST(WorkerPool, EveryElementRunsOnceForEveryWorkerCount) {
  using worker_pool_test::Visits;
  for (const uint32_t threads : {1u, 2u, 3u, 4u, 7u}) {
    sinew::firmware::WorkerPool pool;
    std::string report, error;
    ASSERT_TRUE(pool.start(threads, 0, -1, &report, &error)) << error;
    EXPECT_EQ(pool.threads(), threads);
    for (const uint32_t count : {0u, 1u, 63u, 448u, 4192u, 31248u}) {
      Visits v;
      v.count.assign(count, 0);
      for (int round = 0; round < 20; ++round)
        sinew::layer::run_ranges(pool.workers(), count, worker_pool_test::visit, &v);
      for (uint32_t i = 0; i < count; ++i)
        ASSERT_EQ(v.count[i], 20u) << threads << " threads, element " << i << " of " << count;
    }
  }
}

TEST(WorkerPool, LoopsAllocateNothing) {
  sinew::firmware::WorkerPool pool;
  std::string report, error;
  ASSERT_TRUE(pool.start(3, 0, -1, &report, &error)) << error;
  worker_pool_test::Visits v;
  v.count.assign(4192, 0);
  sinew::layer::run_ranges(pool.workers(), 4192, worker_pool_test::visit, &v);  // warm: first wait
  sinew::test::AllocationCounter allocations;
  for (int round = 0; round < 2000; ++round)
    sinew::layer::run_ranges(pool.workers(), 4192, worker_pool_test::visit, &v);
  EXPECT_EQ(allocations.allocations(), 0u);
  EXPECT_EQ(v.count[0], 2001u);
  EXPECT_EQ(v.count[4191], 2001u);
}

TEST(WorkerPool, RefusesCountsOutsideItsRangeAndRestarts) {
  sinew::firmware::WorkerPool pool;
  std::string report, error;
  EXPECT_FALSE(pool.start(0, 0, -1, &report, &error));
  EXPECT_NE(error.find("workers = 0"), std::string::npos) << error;
  error.clear();
  EXPECT_FALSE(pool.start(sinew::layer::kMaxParts + 1, 0, -1, &report, &error));
  EXPECT_NE(error.find("must be 1.."), std::string::npos) << error;
  ASSERT_TRUE(pool.start(4, 0, -1, &report, &error)) << error;
  pool.stop();
  ASSERT_TRUE(pool.start(2, 0, -1, &report, &error)) << error;
  worker_pool_test::Visits v;
  v.count.assign(1000, 0);
  sinew::layer::run_ranges(pool.workers(), 1000, worker_pool_test::visit, &v);
  for (uint32_t c : v.count) ASSERT_EQ(c, 1u);
}
