// Counts heap allocations between two points of a test:
//   sinew::test::AllocationCounter counter;  // starts counting
//   ... run steps ...
//   EXPECT_EQ(counter.allocations(), 0u);
// Link the test against sinew_test_support; it wraps malloc/calloc/realloc/free
// at link time and replaces the global operator new/delete.
#pragma once

#include <cstdint>

namespace sinew::test {

uint64_t allocation_count();  // total since process start (monotonic)

class AllocationCounter {
 public:
  AllocationCounter() : start_(allocation_count()) {}
  uint64_t allocations() const { return allocation_count() - start_; }

 private:
  uint64_t start_;
};

}  // namespace sinew::test
