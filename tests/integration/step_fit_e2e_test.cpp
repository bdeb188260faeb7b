// End to end through the daemon binary: [loop] step_budget and over_budget
// (firmware/daemon/step_fit.hpp). The arm's metaballs at 20 kHz (a 50 us
// period) is over any budget on any machine, so every assertion below holds
// however fast or loaded the machine is; no assertion is on a time.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <fstream>
#include <regex>
#include <string>

#include "tests/integration/daemon_harness.hpp"

namespace step_fit_e2e_test {

std::string fit_config(const std::string& name, const std::string& loop_extra) {
  const std::string path = testing::TempDir() + "/" + name + ".toml";
  std::ofstream(path) << "[rig]\nbuiltin = \"arm\"\n[loop]\nrate_hz = 20000\nduration_s = 0.2\nstats_interval_s = 0\n"
                      << "mode = \"live\"\n"
                      << loop_extra << "[layers]\nmetaballs = true\n"
                      << "[[source]]\ntype = \"trajectory\"\nperiod_ms = 20\n";
  return path;
}

int exit_code(const sinew::test::DaemonRun& run) { return WIFEXITED(run.status) ? WEXITSTATUS(run.status) : -1; }

TEST(StepFitEndToEnd, RefuseEndsWithTheMeasuredTickAndTheSlowestStage) {
  const sinew::test::DaemonRun run =
      sinew::test::run_sinewd(fit_config("refuse", "over_budget = \"refuse\"\n"), testing::TempDir() + "/refuse.out");
  EXPECT_EQ(exit_code(run), 2) << run.out;
  EXPECT_NE(run.out.find("[loop] over_budget = \"refuse\": a tick needs"), std::string::npos) << run.out;
  // The only layer on: named whichever stage the probe found slowest (under
  // qemu or load skinning can be), since skinning cannot be switched off.
  EXPECT_NE(run.out.find("switch off [layers] metaballs)"), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("switch off [layers] skinning"), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("final tick"), std::string::npos) << run.out;  // no tick ran
}

TEST(StepFitEndToEnd, SlowRunsAtAnExactDivisorAndTheVerdictSaysSo) {
  const sinew::test::DaemonRun run =
      sinew::test::run_sinewd(fit_config("slow", "over_budget = \"slow\"\n"), testing::TempDir() + "/slow.out");
  ASSERT_EQ(exit_code(run), 0) << run.out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(run.out, m, std::regex("slowed to ([0-9]+) Hz"))) << run.out;
  const unsigned rate = static_cast<unsigned>(std::stoul(m[1]));
  EXPECT_LT(rate, 20000u);
  EXPECT_GT(rate, 0u);
  EXPECT_EQ(20000u % rate, 0u) << rate;
  EXPECT_NE(run.out.find("; " + std::to_string(rate) + " Hz, mode live"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("at " + std::to_string(rate) + " Hz (slowed from 20000 Hz to fit)"), std::string::npos)
      << run.out;
}

TEST(StepFitEndToEnd, WarnKeepsTheRateAndSaysWhatWouldFit) {
  const sinew::test::DaemonRun run = sinew::test::run_sinewd(fit_config("warn", ""), testing::TempDir() + "/warn.out");
  ASSERT_EQ(exit_code(run), 0) << run.out;
  EXPECT_NE(run.out.find("warning: a tick needs"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("over_budget = \"slow\" would run at"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("; 20000 Hz, mode live"), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("slowed"), std::string::npos) << run.out;
}

TEST(StepFitEndToEnd, AZeroBudgetMeasuresNothing) {
  const sinew::test::DaemonRun run =
      sinew::test::run_sinewd(fit_config("off", "step_budget = 0\n"), testing::TempDir() + "/off.out");
  ASSERT_EQ(exit_code(run), 0) << run.out;
  EXPECT_EQ(run.out.find("at start-up"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("; 20000 Hz, mode live"), std::string::npos) << run.out;
}

}  // namespace step_fit_e2e_test
