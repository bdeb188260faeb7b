#include "daemon_harness.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

extern char** environ;

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

BackgroundDaemon::BackgroundDaemon(const std::string& config, const std::string& out_path) {
  const std::string command =
      std::string("exec ") + SINEWD_LAUNCHER SINEWD_EXE + " --config " + config + " > " + out_path + " 2>&1";
  const char* argv[] = {"/bin/sh", "-c", command.c_str(), nullptr};
  pid_t pid = -1;
  started_ = posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ) == 0;
  pid_ = pid;
}

BackgroundDaemon::~BackgroundDaemon() {
  if (started_ && !stopped_) kill();
}

bool BackgroundDaemon::running() const { return started_ && !stopped_ && ::waitpid(pid_, nullptr, WNOHANG) == 0; }

int BackgroundDaemon::stop() {
  ::kill(pid_, SIGTERM);
  int status = -1;
  ::waitpid(pid_, &status, 0);
  stopped_ = true;
  return status;
}

void BackgroundDaemon::kill() {
  ::kill(pid_, SIGKILL);
  ::waitpid(pid_, nullptr, 0);
  stopped_ = true;
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
