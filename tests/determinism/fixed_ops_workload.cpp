// Golden determinism of the fixed-point workload. Model: Box2D v3's
// determinism test (one scene, one hash, checked on every platform).
#include "host_tools/determinism/fixed_ops_workload.hpp"

#include <gtest/gtest.h>

#include "host_tools/determinism/output_hash.hpp"
#include "tests/determinism/golden.hpp"
#include "tests/support/alloc_guard.hpp"

namespace det = sinew::determinism;

TEST(Determinism, FixedOpsMatchGolden) {
  sinew::test::AllocationCounter allocations;
  const uint64_t digest = det::run_fixed_ops(det::kFixedOpsIterations);
  EXPECT_EQ(allocations.allocations(), 0u);
  det::print_determinism_line("fixed-ops", digest);
  EXPECT_EQ(digest, sinew::test::golden::kFixedOps) << "fixed-point results changed";
}
