// Golden determinism of the engine step on the default rigs: the compiled blob
// and every step's outputs must hash to the committed values on every build.
#include "host_tools/determinism/engine_workload.hpp"

#include <gtest/gtest.h>

#include "host_tools/determinism/output_hash.hpp"
#include "tests/determinism/golden.hpp"

namespace det = sinew::determinism;
namespace golden = sinew::test::golden;

namespace {
void check(const char* rig, uint64_t golden_blob, uint64_t golden_output) {
  det::EngineRun run;
  std::string error;
  ASSERT_TRUE(det::run_engine_workload(rig, det::kEngineSteps, &run, &error)) << error;
  det::print_determinism_line((std::string(rig) + "-rig-blob").c_str(), run.blob_hash);
  det::print_determinism_line((std::string("engine-") + rig).c_str(), run.output_hash);
  EXPECT_GT(run.clamped_dofs, 0u) << "the trajectory should exercise joint limits";
  EXPECT_EQ(run.blob_hash, golden_blob) << "compiled " << rig << " rig changed";
  EXPECT_EQ(run.output_hash, golden_output) << "engine outputs on the " << rig << " rig changed";
}
}  // namespace

TEST(Determinism, EngineArmMatchesGolden) { check("arm", golden::kArmBlob, golden::kEngineArm); }
TEST(Determinism, EngineHandMatchesGolden) { check("hand", golden::kHandBlob, golden::kEngineHand); }
