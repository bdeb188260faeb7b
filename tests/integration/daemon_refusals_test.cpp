// End to end through the daemon binary: hostile command lines and
// configurations end with a message and a non-zero status, never a crash,
// a hang or a silent default.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "tests/integration/daemon_harness.hpp"
#include "tests/support/planted_links.hpp"

namespace {

// The hand on the built-in sweep, offline, for 0.2 s.
std::string refusal_config(const std::string& name, const std::string& extra) {
  const std::string path = testing::TempDir() + "/" + name + ".toml";
  std::ofstream(path) << "[rig]\nbuiltin = \"hand\"\n[loop]\nrate_hz = 50\nduration_s = 0.2\nstats_interval_s = 0\n"
                      << "mode = \"offline\"\n[[source]]\ntype = \"trajectory\"\nperiod_ms = 20\n"
                      << extra;
  return path;
}

int exit_code(const sinew::test::DaemonRun& run) { return WIFEXITED(run.status) ? WEXITSTATUS(run.status) : -1; }

}  // namespace

// inf and 1e300 once ran zero ticks (an undefined double to integer cast);
// -5 and nan were ignored.
TEST(DaemonEndToEnd, RefusesNonFiniteNegativeAndHugeDurations) {
  const std::string config = refusal_config("duration", "");
  for (const char* duration : {"inf", "1e300", "-5", "nan", "1e8", "ten"}) {
    const sinew::test::DaemonRun run =
        sinew::test::run_sinewd(config + " --duration " + duration, testing::TempDir() + "/duration.out");
    EXPECT_EQ(exit_code(run), 2) << run.command << "\n" << run.out;
    EXPECT_NE(run.out.find("--duration"), std::string::npos) << run.out;
  }
  const sinew::test::DaemonRun ok =
      sinew::test::run_sinewd(config + " --duration 0.1", testing::TempDir() + "/duration.out");
  EXPECT_EQ(exit_code(ok), 0) << ok.out;
  EXPECT_NE(ok.out.find("final tick 5:"), std::string::npos) << ok.out;
}

TEST(DaemonEndToEnd, ADirectoryAsConfigIsNamedAsSuch) {
  const sinew::test::DaemonRun run = sinew::test::run_sinewd(testing::TempDir(), testing::TempDir() + "/dir.out");
  EXPECT_EQ(exit_code(run), 2) << run.out;
  EXPECT_NE(run.out.find("is a directory"), std::string::npos) << run.out;
}

// A trajectory period of 1e300 ms once divided by zero (SIGFPE).
TEST(DaemonEndToEnd, AHugeTrajectoryPeriodIsAnErrorNotACrash) {
  const std::string path = testing::TempDir() + "/huge_period.toml";
  std::ofstream(path) << "[rig]\nbuiltin = \"hand\"\n[loop]\nmode = \"offline\"\nduration_s = 0.1\n"
                      << "[[source]]\ntype = \"trajectory\"\nperiod_ms = 1e300\n";
  const sinew::test::DaemonRun run = sinew::test::run_sinewd(path, testing::TempDir() + "/huge_period.out");
  EXPECT_EQ(exit_code(run), 2) << run.out;
  EXPECT_NE(run.out.find("period_ms"), std::string::npos) << run.out;
}

// A sink that loses frames (here: the file size limit, as a full disk would)
// leaves an incomplete output: the exit status says so.
TEST(DaemonEndToEnd, DroppedFramesMakeTheExitStatusNonZero) {
  const std::string log = testing::TempDir() + "/dropped.log";
  std::remove(log.c_str());
  const std::string config = refusal_config("dropped", "[[sink]]\ntype = \"log\"\npath = \"" + log + "\"\n");
  const std::string out = testing::TempDir() + "/dropped.out";
  // Ignore SIGXFSZ so a write past the limit fails with EFBIG instead.
  const std::string command =
      "trap '' XFSZ; ulimit -f 4; " SINEWD_LAUNCHER SINEWD_EXE " --config " + config + " > " + out + " 2>&1";
  const int status = std::system(command.c_str());
  const std::string text = sinew::test::slurp(out);
  ASSERT_TRUE(WIFEXITED(status)) << text;
  EXPECT_EQ(WEXITSTATUS(status), 1) << command << "\n" << text;
  EXPECT_NE(text.find("frames dropped by the sinks"), std::string::npos) << text;
  std::remove(log.c_str());
}

// Run as root with its log in a shared directory, the daemon wrote through a
// symbolic link another user planted at the log's name (into an empty file it
// gave a header) or at its temporary name "<log>.tmp" (truncating the file).
TEST(DaemonEndToEnd, NeverWritesThroughALinkPlantedAtTheLogOrItsTemporaryName) {
  {
    const sinew::test::LinkTrap trap("");
    trap.plant_symlink("frames.log");
    const std::string config =
        refusal_config("planted_log", "[[sink]]\ntype = \"log\"\npath = \"" + trap.out("frames.log") + "\"\n");
    const sinew::test::DaemonRun run = sinew::test::run_sinewd(config, testing::TempDir() + "/planted_log.out");
    EXPECT_EQ(exit_code(run), 2) << run.out;
    EXPECT_NE(run.out.find("frames.log: is a symbolic link, refusing to follow it"), std::string::npos) << run.out;
    EXPECT_TRUE(trap.victim_untouched());
  }
  {
    const sinew::test::LinkTrap trap;
    trap.plant_symlink("frames.log.tmp");
    const std::string config =
        refusal_config("planted_tmp", "[[sink]]\ntype = \"log\"\npath = \"" + trap.out("frames.log") + "\"\n");
    const sinew::test::DaemonRun run = sinew::test::run_sinewd(config, testing::TempDir() + "/planted_tmp.out");
    EXPECT_EQ(exit_code(run), 0) << run.out;
    EXPECT_TRUE(trap.victim_untouched());
    EXPECT_EQ(sinew::test::read_frame_log(trap.out("frames.log")).poses.size(), 10u);
  }
}

// A live run that cannot keep up skips ticks; it still ends when its
// duration of schedule is over (once, at 20 kHz, a 2 s run lasted 24 s): no
// frame carries a slot beyond the run's last. The frames go to a recording
// (inputs only) through a ring deeper than the run's 10 000 slots, so no
// frame can be dropped however far the I/O thread falls behind on a busy
// machine (a drop would make the exit status 1: docs/testing.md).
TEST(DaemonEndToEnd, DurationIsScheduleTimeEvenWhenTicksAreSkipped) {
  const std::string log = testing::TempDir() + "/fast.log";
  std::remove(log.c_str());
  const std::string path = testing::TempDir() + "/fast.toml";
  std::ofstream(path) << "[rig]\nbuiltin = \"hand\"\n[loop]\nrate_hz = 20000\nduration_s = 0.5\nstats_interval_s = 0\n"
                      << "mode = \"live\"\n[realtime]\nsink_ring_frames = 16384\n"
                      << "[[source]]\ntype = \"trajectory\"\nperiod_ms = 20\n"
                      << "[[sink]]\ntype = \"record\"\npath = \"" << log << "\"\n";
  const sinew::test::DaemonRun run = sinew::test::run_sinewd(path, testing::TempDir() + "/fast.out");
  ASSERT_EQ(exit_code(run), 0) << run.out;
  const sinew::test::FrameLog frames = sinew::test::read_frame_log(log);
  ASSERT_FALSE(frames.poses.empty());
  for (const auto& pose : frames.poses) ASSERT_LT(pose.tick, 10000u) << run.out;
  std::remove(log.c_str());
}

namespace {

// sinewd with raw arguments (no --config); its status and output.
sinew::test::DaemonRun run_sinewd_args(const std::string& args, const std::string& out_path) {
  sinew::test::DaemonRun run;
  run.command = std::string(SINEWD_LAUNCHER SINEWD_EXE) + " " + args + " > " + out_path + " 2>&1";
  run.status = std::system(run.command.c_str());
  run.out = sinew::test::slurp(out_path);
  return run;
}

}  // namespace

// --check-config validates without running (exit 0, the configuration with
// every key resolved) or names file:line:key (exit 2);
// --print-default-config is itself a configuration --check-config accepts.
TEST(DaemonEndToEnd, CheckConfigAndPrintDefaultConfig) {
  const std::string dir = testing::TempDir();
  const std::string good = refusal_config("check_good", "");
  const sinew::test::DaemonRun ok = run_sinewd_args("--check-config " + good, dir + "/check_good.out");
  EXPECT_EQ(exit_code(ok), 0) << ok.out;
  EXPECT_NE(ok.out.find("valid"), std::string::npos) << ok.out;
  EXPECT_NE(ok.out.find("rate_hz = 50\n"), std::string::npos) << ok.out;            // the file's value
  EXPECT_NE(ok.out.find("sink_ring_frames = 128\n"), std::string::npos) << ok.out;  // a default filled in
  EXPECT_EQ(ok.out.find("final tick"), std::string::npos) << ok.out;                // nothing ran

  const std::string bad = testing::TempDir() + "/check_bad.toml";
  std::ofstream(bad) << "[rig]\nbuiltin = \"hand\"\n[loop]\nrate_hz = 0\n";
  const sinew::test::DaemonRun refused = run_sinewd_args("--check-config " + bad, dir + "/check_bad.out");
  EXPECT_EQ(exit_code(refused), 2) << refused.out;
  EXPECT_NE(refused.out.find("check_bad.toml:4: rate_hz"), std::string::npos) << refused.out;

  const std::string defaults = dir + "/defaults.toml";
  const sinew::test::DaemonRun printed = run_sinewd_args("--print-default-config", defaults);
  ASSERT_EQ(exit_code(printed), 0) << printed.out;
  const sinew::test::DaemonRun checked = run_sinewd_args("--check-config " + defaults, dir + "/defaults_check.out");
  EXPECT_EQ(exit_code(checked), 0) << checked.out;
}

// [realtime] user: a user sinewd cannot become is refused before anything
// runs; started as root, it runs as the user after opening its outputs.
TEST(DaemonEndToEnd, RunsAsTheConfiguredUserOrRefusesBeforeRunning) {
  const sinew::test::DaemonRun refused = sinew::test::run_sinewd(
      refusal_config("no_user", "[realtime]\nuser = \"no_such_user_x\"\n"), testing::TempDir() + "/no_user.out");
  EXPECT_EQ(exit_code(refused), 2) << refused.out;
  EXPECT_NE(refused.out.find("[realtime] user = \"no_such_user_x\": no such user"), std::string::npos) << refused.out;
  EXPECT_EQ(refused.out.find("rig hand"), std::string::npos) << refused.out;  // refused before the rig was loaded
  if (::geteuid() != 0) GTEST_SKIP() << "switching users needs root";
  const std::string log = testing::TempDir() + "/as_nobody.log";
  std::remove(log.c_str());
  const sinew::test::DaemonRun run = sinew::test::run_sinewd(
      refusal_config("as_nobody", "[realtime]\nuser = \"nobody\"\n[[sink]]\ntype = \"log\"\npath = \"" + log + "\"\n"),
      testing::TempDir() + "/as_nobody.out");
  EXPECT_EQ(exit_code(run), 0) << run.out;
  EXPECT_NE(run.out.find("running as user nobody"), std::string::npos) << run.out;
  EXPECT_FALSE(sinew::test::read_frame_log(log).poses.empty());  // opened as root, written as nobody
  std::remove(log.c_str());
}
