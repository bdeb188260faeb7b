// sinew-log: verify reports intact, gapped, disordered and damaged logs
// truthfully (and its exit status says which), dump prints every frame.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "host_tools/log/log_check.hpp"
#include "tests/hal/output/frame_log_fixture.hpp"

namespace sinew::test {
namespace {

struct ToolRun {
  int status = -1;
  std::string out;
};

ToolRun run_sinew_log(const std::string& args, const std::string& out_path) {
  const std::string command = std::string(SINEW_LOG_EXE) + " " + args + " > " + out_path + " 2>&1";
  const int raw = std::system(command.c_str());
  ToolRun r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream in(out_path);
  std::stringstream ss;
  ss << in.rdbuf();
  r.out = ss.str();
  return r;
}

using LogToolTest = FrameLogTest;

TEST_F(LogToolTest, AnIntactLogIsOk) {
  const std::string path = dir_.file("intact.log");
  write_frames(path, 0, kFrames);
  log_tool::LogCheck c;
  std::string error;
  ASSERT_TRUE(log_tool::check_log(path, &c, &error)) << error;
  EXPECT_TRUE(c.ok());
  EXPECT_EQ(c.frames, kFrames);
  EXPECT_EQ(c.first_tick, 0u);
  EXPECT_EQ(c.last_tick, kFrames - 1);
  EXPECT_EQ(c.tick_gaps, 0u);
  const ToolRun run = run_sinew_log("verify " + path, dir_.file("intact.out"));
  EXPECT_EQ(run.status, 0) << run.out;
  EXPECT_NE(run.out.find("5 frames, ticks 0..4"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("\nok\n"), std::string::npos) << run.out;
}

// Skipped ticks (a late tick is skipped, not burst) leave gaps: reported,
// not an error. A repeated tick is an error; a lower one starts a new run
// (a restarted daemon appends to its log).
TEST_F(LogToolTest, GapsAreCountedAndDisorderFails) {
  const std::string gapped = dir_.file("gapped.log");
  poses_[3]->set_tick(7);
  poses_[4]->set_tick(8);
  write_frames(gapped, 0, kFrames);
  log_tool::LogCheck c;
  std::string error;
  ASSERT_TRUE(log_tool::check_log(gapped, &c, &error)) << error;
  EXPECT_TRUE(c.ok());
  EXPECT_EQ(c.tick_gaps, 1u);
  EXPECT_EQ(c.missing_ticks, 4u);

  const std::string appended = dir_.file("appended.log");
  poses_[3]->set_tick(3);
  poses_[4]->set_tick(4);
  write_frames(appended, 0, kFrames);
  write_frames(appended, 0, kFrames);
  ASSERT_TRUE(log_tool::check_log(appended, &c, &error)) << error;
  EXPECT_TRUE(c.ok());
  EXPECT_EQ(c.runs, 2u);
  EXPECT_EQ(c.frames, 2 * kFrames);

  const std::string disordered = dir_.file("disordered.log");
  poses_[3]->set_tick(2);
  write_frames(disordered, 0, kFrames);
  ASSERT_TRUE(log_tool::check_log(disordered, &c, &error)) << error;
  EXPECT_FALSE(c.ok());
  EXPECT_EQ(c.tick_disorder, 1u);
  const ToolRun run = run_sinew_log("verify " + gapped + " " + disordered, dir_.file("disorder.out"));
  EXPECT_EQ(run.status, 1) << run.out;
  EXPECT_NE(run.out.find("repeating the tick"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("FAILED"), std::string::npos) << run.out;
}

TEST_F(LogToolTest, ATornTailIsDamageAndTheIntactFramesAreCounted) {
  const std::string path = dir_.file("torn.log");
  const std::vector<uint64_t> ends = write_frames(path, 0, kFrames);
  ASSERT_EQ(::truncate(path.c_str(), static_cast<off_t>(ends.back() - 5)), 0);
  log_tool::LogCheck c;
  std::string error;
  ASSERT_TRUE(log_tool::check_log(path, &c, &error)) << error;
  EXPECT_FALSE(c.ok());
  EXPECT_EQ(c.frames, kFrames - 1);
  const ToolRun run = run_sinew_log("verify " + path, dir_.file("torn.out"));
  EXPECT_EQ(run.status, 1) << run.out;
  EXPECT_NE(run.out.find("damaged: torn-tail"), std::string::npos) << run.out;
}

TEST_F(LogToolTest, AFileThatIsNotALogIsExitTwo) {
  const std::string path = dir_.file("not.log");
  std::ofstream(path) << "hello, not a frame log, but long enough to hold a header of forty bytes\n";
  const ToolRun run = run_sinew_log("verify " + path, dir_.file("not.out"));
  EXPECT_EQ(run.status, 2) << run.out;
  EXPECT_NE(run.out.find(path), std::string::npos) << run.out;
}

TEST_F(LogToolTest, DumpPrintsOneLinePerFrame) {
  const std::string path = dir_.file("dump.log");
  write_frames(path, 0, kFrames);
  ToolRun run = run_sinew_log("dump " + path + " --vertices 2", dir_.file("dump.out"));
  EXPECT_EQ(run.status, 0) << run.out;
  size_t lines = 0;
  for (char ch : run.out) lines += ch == '\n';
  EXPECT_EQ(lines, kFrames + 1) << run.out;  // a header line, then the frames
  EXPECT_NE(run.out.find("\n3 1003000000 ["), std::string::npos) << run.out;
  run = run_sinew_log("dump " + path + " --from 2 --count 2", dir_.file("dump2.out"));
  EXPECT_EQ(run.status, 0) << run.out;
  EXPECT_NE(run.out.find("\n2 "), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("\n3 "), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("\n4 "), std::string::npos) << run.out;
}

}  // namespace
}  // namespace sinew::test
