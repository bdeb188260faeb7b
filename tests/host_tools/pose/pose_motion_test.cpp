// sinew-pose --spec --motion: a BVH take (joints renamed through the spec's
// [motion.bvh_joints]) or CSV joint tracks drive the rig's inputs through the
// pipeline. A 90 degree BVH elbow flexion is the elbow input at 90 degrees to
// the binary angle's last bit and poses the skin exactly as CSV tracks
// commanding 90 degrees do; bad tables and files are refused by name.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include "host_tools/rigc/gltf_poser.hpp"
#include "synthetic_gltf.hpp"

namespace {

using sinew::oracle::testing::temp_path;

// The built-in arm's elbow flexes about z (rigs/arm.toml); the take names
// its joints as a motion-capture skeleton does.
const char* const kMotionTake = R"(HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT RightArm
  {
    OFFSET 0 1 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT RightForeArm
    {
      OFFSET 0 1 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {
        OFFSET 0 1 0
      }
    }
  }
}
MOTION
Frames: 3
Frame Time: 0.1
0 0 0 0 0 0 0 0 0 0 0 0
0 0 0 0 0 0 0 0 0 45 0 0
0 0 0 0 0 0 0 0 0 90 0 0
)";

std::string motion_write(const std::string& name, const std::string& text) {
  const std::string path = temp_path(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string motion_spec(const std::string& name, const std::string& motion_table) {
  return motion_write(name, "[rig]\nsource = \"builtin:arm\"\n\n" + motion_table);
}

int motion_run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

std::string motion_slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The error open_spec + set_motion give, or "" when both succeed.
std::string motion_error(const std::string& spec, const std::string& take) {
  sinew::rigc::GltfPoser poser;
  std::string error;
  if (!poser.open_spec(spec, 100, &error, false) || !poser.set_motion(take, &error)) return error;
  return "";
}

constexpr size_t kElbowInput = 3;  // shoulder.0-2, then elbow.0

TEST(PoseMotion, ARenamedBvhElbowFlexionIsTheElbowInput) {
  const std::string spec = motion_spec("motion_arm.toml", "[motion.bvh_joints]\nelbow = \"RightForeArm\"\n");
  const std::string take = motion_write("motion_take.bvh", kMotionTake);
  sinew::rigc::GltfPoser bvh_poser, csv_poser;
  std::string error;
  ASSERT_TRUE(bvh_poser.open_spec(spec, 100, &error, false)) << error;
  ASSERT_TRUE(bvh_poser.set_motion(take, &error)) << error;
  std::vector<std::array<double, 3>> from_bvh, from_csv;
  ASSERT_TRUE(bvh_poser.pose_motion(0.2, &from_bvh, &error)) << error;
  const std::vector<int32_t>& inputs = bvh_poser.motion_inputs();
  ASSERT_GT(inputs.size(), kElbowInput);
  // 90 degrees is a quarter turn, 2^30 in the binary angle (2^32 per turn).
  const int64_t quarter = int64_t{1} << 30;
  EXPECT_LE(std::llabs(int64_t{inputs[kElbowInput]} - quarter), 1) << inputs[kElbowInput];
  std::printf("BVH elbow 90 deg -> elbow input %d (2^30 = %lld)\n", inputs[kElbowInput],
              static_cast<long long>(quarter));
  for (size_t i = 0; i < inputs.size(); ++i)
    if (i != kElbowInput) EXPECT_EQ(inputs[i], 0) << "input " << i << ": unmapped joints stay at rest";

  // The same pose commanded by CSV joint tracks: the same skin, bit for bit.
  const std::string csv = motion_write("motion_elbow.csv", "time,elbow.0\n0,0\n0.1,45\n0.2,90\n");
  ASSERT_TRUE(csv_poser.open_spec(spec, 100, &error, false)) << error;
  ASSERT_TRUE(csv_poser.set_motion(csv, &error)) << error;
  ASSERT_TRUE(csv_poser.pose_motion(0.2, &from_csv, &error)) << error;
  EXPECT_EQ(csv_poser.motion_inputs(), inputs);
  ASSERT_FALSE(from_bvh.empty());
  EXPECT_EQ(from_bvh, from_csv);

  // And the rest pose differs from the flexed one (the input moves the skin).
  std::vector<std::array<double, 3>> at_rest;
  ASSERT_TRUE(bvh_poser.pose_motion(0.0, &at_rest, &error)) << error;
  EXPECT_NE(at_rest, from_bvh);
}

TEST(PoseMotion, TheCommandWritesTheFlexedSkin) {
  const std::string spec = motion_spec("motion_cli.toml", "[motion.bvh_joints]\nelbow = \"RightForeArm\"\n");
  const std::string take = motion_write("motion_cli.bvh", kMotionTake);
  const std::string out = temp_path("motion_cli.csv"), log = temp_path("motion_cli.log");
  std::remove(out.c_str());
  ASSERT_EQ(motion_run(std::string(SINEW_POSE_EXE) + " --spec " + spec + " --motion " + take +
                       " --time 0 --time 0.2 --out " + out + " 2>" + log),
            0)
      << motion_slurp(log);
  const std::string csv = motion_slurp(out);
  EXPECT_NE(csv.find("motion " + take), std::string::npos);
  EXPECT_NE(csv.find("# time 0.2 s"), std::string::npos);
  // --motion needs a spec.
  EXPECT_EQ(motion_run(std::string(SINEW_POSE_EXE) + " " + take + " --motion " + take + " --time 0 --out " + out +
                       " 2>" + log),
            1);
  EXPECT_NE(motion_slurp(log).find("--motion needs --spec"), std::string::npos) << motion_slurp(log);
  // A missing BVH joint fails the command with its name.
  const std::string bad = motion_spec("motion_cli_bad.toml", "[motion.bvh_joints]\nelbow = 'LeftForeArm'\n");
  EXPECT_EQ(motion_run(std::string(SINEW_POSE_EXE) + " --spec " + bad + " --motion " + take + " --time 0 --out " + out +
                       " 2>" + log),
            1);
  EXPECT_NE(motion_slurp(log).find("'LeftForeArm'"), std::string::npos) << motion_slurp(log);
}

TEST(PoseMotion, BadTablesAndFilesAreRefusedByName) {
  const std::string take = motion_write("motion_errors.bvh", kMotionTake);
  struct Case {
    const char* table;
    const char* expected;  // in the message
  };
  const Case cases[] = {
      {"[motion.bvh_joints]\nelbow = 3\n", "motion_e.toml:5: [motion.bvh_joints] elbow must be a BVH joint name"},
      {"[motion.bvh_joints]\nelbow = \"\"\n", "[motion.bvh_joints] elbow must be a BVH joint name"},
      {"[motion]\nbvh_joint = { elbow = \"RightForeArm\" }\n", "motion_e.toml:5: [motion] bvh_joint: unknown key"},
      {"[motion]\nbvh_joints = \"RightForeArm\"\n", "[motion] bvh_joints must be a table"},
      {"[[motion]]\n", "[motion] must be a table"},
      {"[motion.bvh_joints]\nknee = \"RightForeArm\"\n", "[motion.bvh_joints] knee: the rig has no joint 'knee'"},
      {"[motion.bvh_joints]\nelbow = 'LeftForeArm'\n", "the BVH file has no joint 'LeftForeArm'"},
      {"", "no rig joint ('shoulder', 'elbow', 'forearm_twist', 'wrist') names a BVH joint"},
  };
  for (const Case& c : cases) {
    const std::string spec = motion_spec("motion_e.toml", c.table);
    const std::string error = motion_error(spec, take);
    EXPECT_NE(error.find(c.expected), std::string::npos) << c.table << "\n -> " << error;
  }
  const std::string spec = motion_spec("motion_ok.toml", "[motion.bvh_joints]\nelbow = \"RightForeArm\"\n");
  const std::string nan_take =
      motion_write("motion_nan.bvh", std::string(kMotionTake).replace(std::string(kMotionTake).rfind("90"), 2, "nan"));
  EXPECT_NE(motion_error(spec, nan_take).find("line 26: frame 3, value 10 (joint 'RightForeArm' Zrotation)"),
            std::string::npos)
      << motion_error(spec, nan_take);
  const std::string csv = motion_write("motion_unknown.csv", "time,knee.0\n0,1\n");
  EXPECT_NE(motion_error(spec, csv).find("column 'knee.0' names no rig input"), std::string::npos)
      << motion_error(spec, csv);
}

}  // namespace
