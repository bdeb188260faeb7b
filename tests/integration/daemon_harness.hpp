// Runs the daemon binary on a config file and reads back what it wrote: the
// shared plumbing of the end-to-end tests.
#pragma once

#include <string>
#include <vector>

#include "hal/output/frame_log_reader.hpp"

namespace sinew::test {

// The built-in arm's inputs: shoulder.0-2 are 0-2, elbow.0 is 3,
// forearm_twist.0 is 4, wrist.0-1 are 5-6; external inputs follow.
inline constexpr int kArmElbow = 3, kArmTwist = 4, kArmInputs = 7;

// The whole content of a text file ("" if it cannot be read).
std::string slurp(const std::string& path);

struct DaemonRun {
  int status = -1;  // std::system's status; 0 when the daemon exited 0
  std::string command;
  std::string out;  // the daemon's stdout and stderr
};

// Starts `SINEWD_LAUNCHER SINEWD_EXE --config CONFIG` (through the emulator
// in a cross build) and waits for it; its output goes to OUT_PATH.
DaemonRun run_sinewd(const std::string& config_path, const std::string& out_path);

// The daemon in the background (through the launcher, as run_sinewd) until
// stop() or destruction (SIGKILL); its output goes to out_path.
class BackgroundDaemon {
 public:
  BackgroundDaemon(const std::string& config, const std::string& out_path);
  ~BackgroundDaemon();
  BackgroundDaemon(const BackgroundDaemon&) = delete;
  BackgroundDaemon& operator=(const BackgroundDaemon&) = delete;
  bool started() const { return started_; }
  bool running() const;
  // SIGTERM, then its exit status (the daemon ends its run and exits 0).
  int stop();
  // SIGKILL, as a crash or a power cut would end it.
  void kill();

 private:
  int pid_ = -1;
  bool started_ = false, stopped_ = false;
};

struct FrameLog {
  std::vector<hal::output::DecodedPose> poses;  // every complete frame, in order
  std::string stop;                             // why the reader stopped
};

// Every frame of a frame log; a log that cannot be opened fails the test.
FrameLog read_frame_log(const std::string& path);

}  // namespace sinew::test
