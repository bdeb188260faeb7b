// sinew-run: the main job on the built-in default workload. Prints the
// determinism hash (comparable across builds) and the time it took.
#include <chrono>
#include <cstdio>

#include "host_tools/determinism/fixed_ops_workload.hpp"
#include "host_tools/determinism/output_hash.hpp"

int main() {
  namespace det = sinew::determinism;
  const auto start = std::chrono::steady_clock::now();
  const uint64_t digest = det::run_fixed_ops(det::kFixedOpsIterations);
  const auto elapsed = std::chrono::steady_clock::now() - start;
  det::print_determinism_line("fixed-ops", digest);
  const double ms = std::chrono::duration<double, std::milli>(elapsed).count();
  std::printf("fixed-ops: %d iterations in %.1f ms (%.2f us/iteration)\n", det::kFixedOpsIterations, ms,
              1000.0 * ms / det::kFixedOpsIterations);
  return 0;
}
