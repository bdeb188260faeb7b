// A recording regenerates its run: the daemon, live, on the simulated rig
// with faults on its inputs and every layer of the arm on, writes a full-mesh
// frame log and a recording; `sinew-log render` of the recording is the
// frame log byte for byte, at a fraction of its size; a zstd-compressed frame
// log of the same run holds the same frames. Renders against another
// rig, of a plain frame log, or over an existing file are refused.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "tests/integration/daemon_harness.hpp"

namespace {

struct Tool {
  int status = -1;
  std::string out;
};

Tool run_sinew_log_tool(const std::string& args, const std::string& out_path) {
  const std::string command = std::string(SINEW_LOG_EXE) + " " + args + " > " + out_path + " 2>&1";
  const int raw = std::system(command.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, sinew::test::slurp(out_path)};
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST(RecordingEndToEnd, ARenderOfTheRecordingIsTheFrameLogByteForByte) {
  const std::string dir = testing::TempDir() + "/recording_e2e";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string config = dir + "/run.toml";
  std::ofstream(config) << "[rig]\nbuiltin = \"arm\"\n[inputs]\ndefault_period_ms = 10.0\n"
                        << "[loop]\nrate_hz = 100\nduration_s = 2.0\nstats_interval_s = 0\nmode = \"live\"\n"
                        // Rings deeper than the run's 200 slots: no frame can
                        // be dropped however far a busy machine delays the
                        // I/O threads (docs/testing.md).
                        << "[realtime]\nsink_ring_frames = 256\n"
                        << "[layers]\nsph = true\nmetaballs = true\nbarnet = true\nanatomy = true\n"
                        << "[[source]]\ntype = \"simulated-rig\"\nname = \"rig\"\nperiod_ms = 10.0\n"
                        << "[[source.fault]]\nkind = \"corrupt\"\nfrom_s = 0.2\nto_s = 0.3\n"
                        << "[[source.fault]]\nkind = \"out-of-range\"\ninput = \"elbow.0\"\nfrom_s = 0.5\nto_s = 0.6\n"
                        << "[[source.fault]]\nkind = \"drop\"\ninput = \"shoulder.0\"\nfrom_s = 0.8\nto_s = 1.1\n"
                        << "[[source.fault]]\nkind = \"bus-off\"\nfrom_s = 1.4\nto_s = 1.6\n"
                        << "[[sink]]\ntype = \"log\"\nname = \"full\"\nnormals = true\npath = \"" << dir
                        << "/full.log\"\n"
                        << "[[sink]]\ntype = \"log\"\nname = \"packed\"\nnormals = true\ncompression = \"zstd\"\n"
                        << "key_every_frames = 50\npath = \"" << dir << "/packed.log\"\n"
                        << "[[sink]]\ntype = \"record\"\nname = \"rec\"\npath = \"" << dir << "/run.rec\"\n";
  const sinew::test::DaemonRun run = sinew::test::run_sinewd(config, dir + "/daemon.out");
  ASSERT_EQ(run.status, 0) << run.out;

  const Tool render = run_sinew_log_tool(
      "render " + dir + "/run.rec --rig builtin:arm --normals -o " + dir + "/rendered.log", dir + "/render.out");
  ASSERT_EQ(render.status, 0) << render.out;
  const std::string full = file_bytes(dir + "/full.log"), rendered = file_bytes(dir + "/rendered.log");
  ASSERT_GT(full.size(), 100000u);
  EXPECT_TRUE(full == rendered) << "the render differs from the live run's frame log (" << rendered.size() << " vs "
                                << full.size() << " bytes)";
  // Faults happened: some input was flagged in the frames (the recording keeps the flags).
  const sinew::test::FrameLog log = sinew::test::read_frame_log(dir + "/full.log");
  size_t flagged = 0;
  for (const auto& pose : log.poses)
    for (uint8_t s : pose.input_status) flagged += (s & (sinew::hal::kJointStale | sinew::hal::kJointRejected)) != 0;
  EXPECT_GT(flagged, 0u);
  // The same run zstd-compressed (deltas between keys every 50 frames): the
  // same frames, read back through keys and deltas, in a smaller file (at
  // 100 Hz with every layer on, frames differ more than at 1 kHz: about
  // 1.6x here against 19x for the default job at 1 kHz).
  const Tool verify = run_sinew_log_tool("verify " + dir + "/full.log " + dir + "/packed.log", dir + "/verify.out");
  ASSERT_EQ(verify.status, 0) << verify.out;
  const size_t first_hash = verify.out.find("content xxh64 ");
  const size_t second_hash = verify.out.find("content xxh64 ", first_hash + 1);
  ASSERT_NE(second_hash, std::string::npos) << verify.out;
  EXPECT_EQ(verify.out.substr(first_hash, 30), verify.out.substr(second_hash, 30)) << verify.out;
  EXPECT_NE(verify.out.find("records zstd-compressed"), std::string::npos) << verify.out;
  EXPECT_LT(std::filesystem::file_size(dir + "/packed.log"), full.size());
  const auto recording_bytes = std::filesystem::file_size(dir + "/run.rec");
  EXPECT_LT(recording_bytes * 100, full.size()) << "a recording is inputs only";

  // Refusals: another rig, a frame log that is not a recording, an existing output.
  Tool refused =
      run_sinew_log_tool("render " + dir + "/run.rec --rig builtin:hand -o " + dir + "/x.log", dir + "/refused.out");
  EXPECT_EQ(refused.status, 2) << refused.out;
  EXPECT_NE(refused.out.find("is not the rig of"), std::string::npos) << refused.out;
  refused =
      run_sinew_log_tool("render " + dir + "/full.log --rig builtin:arm -o " + dir + "/x.log", dir + "/refused.out");
  EXPECT_EQ(refused.status, 2) << refused.out;
  EXPECT_NE(refused.out.find("not a recording"), std::string::npos) << refused.out;
  refused =
      run_sinew_log_tool("render " + dir + "/run.rec --rig builtin:arm -o " + dir + "/full.log", dir + "/refused.out");
  EXPECT_EQ(refused.status, 2) << refused.out;
  EXPECT_NE(refused.out.find("exists"), std::string::npos) << refused.out;
}
