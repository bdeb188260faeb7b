// rigsim --motion: a BVH take (joints renamed by the spec's
// [motion.bvh_joints]) sends the same joint-stream frames as CSV joint tracks
// commanding the same DOF values, which differ from the swing; CSV tracks
// still play as before; a bad take is one message and exit code 2.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

namespace {

std::string rigsim_temp(const std::string& name) {
  return ::testing::TempDir() + "rigsim_" + std::to_string(getpid()) + "_" + name;
}

std::string rigsim_write(const std::string& name, const std::string& text) {
  const std::string path = rigsim_temp(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string rigsim_slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

int rigsim_run(const std::string& args) {
  const int status = std::system((std::string(SINEW_RIGSIM_EXE) + " " + args).c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

// The candump -L lines without their wall-clock timestamps: "can0 ID#DATA".
std::string rigsim_frames(const std::string& log_path) {
  std::istringstream in(rigsim_slurp(log_path));
  std::string line, out;
  while (std::getline(in, line)) {
    const size_t space = line.find(") ");
    out += (space == std::string::npos ? line : line.substr(space + 2)) + "\n";
  }
  return out;
}

const char* const kRigsimTake = R"(HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 3 Xposition Yposition Zposition
  JOINT RightForeArm
  {
    OFFSET 0 1 0
    CHANNELS 3 Yrotation Zrotation Xrotation
    End Site
    {
      OFFSET 0 1 0
    }
  }
}
MOTION
Frames: 3
Frame Time: 0.1
0 0 0 0 0 0
0 0 0 0 45 0
0 0 0 0 90 0
)";

TEST(RigsimMotion, ABvhTakeSendsWhatTheSameCsvTracksSend) {
  const std::string spec =
      rigsim_write("arm.toml", "[rig]\nsource = \"builtin:arm\"\n[motion.bvh_joints]\nelbow = \"RightForeArm\"\n");
  const std::string take = rigsim_write("take.bvh", kRigsimTake);
  // Every arm input, so that none keeps the swing: the BVH leaves unmapped joints at rest.
  const std::string csv = rigsim_write("take.csv",
                                       "time,shoulder.0,shoulder.1,shoulder.2,elbow.0,forearm_twist.0,wrist.0,wrist.1\n"
                                       "0,0,0,0,0,0,0,0\n0.1,0,0,0,45,0,0,0\n0.2,0,0,0,90,0,0,0\n");
  const std::string from_bvh = rigsim_temp("bvh.log"), from_csv = rigsim_temp("csv.log"),
                    swing = rigsim_temp("swing.log"), out = rigsim_temp("out.txt");
  const std::string common = " --duration 0.3 --period-ms 10 >" + out + " 2>&1 --candump ";
  ASSERT_EQ(rigsim_run("--spec " + spec + " --motion " + take + common + from_bvh), 0) << rigsim_slurp(out);
  ASSERT_EQ(rigsim_run("--spec " + spec + " --motion " + csv + common + from_csv), 0) << rigsim_slurp(out);
  ASSERT_EQ(rigsim_run("--spec " + spec + common + swing), 0) << rigsim_slurp(out);
  const std::string bvh_frames = rigsim_frames(from_bvh);
  EXPECT_GT(bvh_frames.size(), 100u) << bvh_frames;
  EXPECT_EQ(bvh_frames, rigsim_frames(from_csv));
  EXPECT_NE(bvh_frames, rigsim_frames(swing)) << "the take, not the swing, drives the rig";
  // The built-in arm from --rig plays the CSV tracks as before.
  ASSERT_EQ(rigsim_run("--rig arm --motion " + csv + common + from_csv), 0) << rigsim_slurp(out);
  EXPECT_EQ(bvh_frames, rigsim_frames(from_csv));
}

TEST(RigsimMotion, ABadTakeIsOneMessage) {
  const std::string spec =
      rigsim_write("bad.toml", "[rig]\nsource = \"builtin:arm\"\n[motion.bvh_joints]\nelbow = \"LeftForeArm\"\n");
  const std::string take = rigsim_write("bad.bvh", kRigsimTake);
  const std::string out = rigsim_temp("bad.txt");
  EXPECT_EQ(rigsim_run("--spec " + spec + " --motion " + take + " --duration 0.1 >" + out + " 2>&1"), 2);
  EXPECT_NE(rigsim_slurp(out).find("the BVH file has no joint 'LeftForeArm'"), std::string::npos) << rigsim_slurp(out);
  const std::string typo = rigsim_write("typo.toml", "[rig]\nsource = \"builtin:arm\"\n[motion]\nbvh_joint = {}\n");
  EXPECT_EQ(rigsim_run("--spec " + typo + " --motion " + take + " --duration 0.1 >" + out + " 2>&1"), 2);
  EXPECT_NE(rigsim_slurp(out).find("typo.toml:4: [motion] bvh_joint: unknown key"), std::string::npos)
      << rigsim_slurp(out);
}

}  // namespace
