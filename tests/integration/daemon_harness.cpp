#include "daemon_harness.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace sinew::test {

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

DaemonRun run_sinewd(const std::string& config_path, const std::string& out_path) {
  DaemonRun run;
  run.command = std::string(SINEWD_LAUNCHER SINEWD_EXE) + " --config " + config_path + " > " + out_path + " 2>&1";
  run.status = std::system(run.command.c_str());
  run.out = slurp(out_path);
  return run;
}

FrameLog read_frame_log(const std::string& path) {
  FrameLog log;
  hal::output::FrameLogReader reader;
  std::string error;
  EXPECT_TRUE(reader.open(path, &error)) << path << ": " << error;
  hal::output::DecodedPose pose;
  while (reader.next(&pose)) log.poses.push_back(pose);
  log.stop = reader.stop_message();
  return log;
}

}  // namespace sinew::test
