// BVH joints driving rig DOFs (host_tools/motion/bvh_drive.hpp): every
// rotation order against an independent composition (rotation matrices in
// double, the twist read back from the matrix), and the mapping's errors.
#include "host_tools/motion/bvh_drive.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "host_tools/motion/bvh.hpp"

namespace sinew::motion {
namespace {

using Mat3 = std::array<std::array<double, 3>, 3>;

Mat3 drive_axis_matrix(int axis, double degrees) {
  const double a = degrees * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
  Mat3 m{};
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;
  m[static_cast<size_t>(axis)][static_cast<size_t>(axis)] = 1;
  m[static_cast<size_t>(i)][static_cast<size_t>(i)] = c;
  m[static_cast<size_t>(j)][static_cast<size_t>(j)] = c;
  m[static_cast<size_t>(i)][static_cast<size_t>(j)] = -s;
  m[static_cast<size_t>(j)][static_cast<size_t>(i)] = s;
  return m;
}

Mat3 drive_mul(const Mat3& a, const Mat3& b) {
  Mat3 m{};
  for (size_t r = 0; r < 3; ++r)
    for (size_t c = 0; c < 3; ++c)
      for (size_t k = 0; k < 3; ++k) m[r][c] += a[r][k] * b[k][c];
  return m;
}

// Twist of a rotation matrix about a unit axis: with angle t about unit n,
// q = (cos t/2, sin t/2 n), and the twist is 2 atan2(sin(t/2) n.a, cos(t/2)).
// sin t n comes from the skew part of R, cos t from its trace.
double drive_twist_of_matrix(const Mat3& m, const Vec3& axis) {
  const Vec3 v{(m[2][1] - m[1][2]) / 2, (m[0][2] - m[2][0]) / 2, (m[1][0] - m[0][1]) / 2};
  const double sin_t = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  const double cos_t = (m[0][0] + m[1][1] + m[2][2] - 1) / 2;
  const double t = std::atan2(sin_t, cos_t);
  const double along = sin_t > 0 ? (v[0] * axis[0] + v[1] * axis[1] + v[2] * axis[2]) / sin_t : 0.0;
  double deg = 2 * std::atan2(std::sin(t / 2) * along, std::cos(t / 2)) * 180.0 / std::numbers::pi;
  if (deg > 180) deg -= 360;
  if (deg <= -180) deg += 360;
  return deg;
}

std::string drive_bvh(const std::string& joint, const std::string& channels, const std::string& row) {
  return "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 3 Xposition Yposition Zposition\n JOINT " + joint +
         "\n {\n  OFFSET 0 1 0\n  CHANNELS 3 " + channels +
         "\n  End Site\n  {\n   OFFSET 0 1 0\n  }\n }\n}\nMOTION\nFrames: 2\nFrame Time: 0.04\n0 0 0 0 0 0\n0 0 0 " +
         row + "\n";
}

TEST(BvhDrive, EveryRotationOrderMatchesAnIndependentComposition) {
  const std::array<char, 3> axes_letters{'X', 'Y', 'Z'};
  const std::array<double, 3> degrees_per_axis{35.0, -62.0, 118.0};  // X, Y, Z channel values
  const double r = 1.0 / std::sqrt(3.0);
  const std::vector<RigJointDofs> rig = {
      {"wrist", true, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}},
      {"tilted", true, {{r, r, r}}},
  };
  std::array<int, 3> order{0, 1, 2};  // XYZ, then the 5 other permutations in lexicographic order
  int permutations = 0;
  double largest_difference = 0;
  do {
    std::string channels, row;
    Mat3 m = drive_axis_matrix(0, 0);
    for (const int a : order) {
      channels += std::string(1, axes_letters[static_cast<size_t>(a)]) + "rotation ";
      row += std::to_string(degrees_per_axis[static_cast<size_t>(a)]) + " ";
      // BVH: the first listed channel is the outermost factor.
      m = drive_mul(m, drive_axis_matrix(a, degrees_per_axis[static_cast<size_t>(a)]));
    }
    SCOPED_TRACE(channels);
    Bvh bvh;
    std::string error;
    ASSERT_TRUE(parse_bvh(drive_bvh("Hand", channels, row), &bvh, &error)) << error;
    JointTracks tracks;
    ASSERT_TRUE(bvh_to_joint_tracks(bvh, rig, {{"wrist", "Hand", "t"}, {"tilted", "Hand", "t"}}, &tracks, &error))
        << error;
    ASSERT_EQ(tracks.tracks.size(), 4u);
    ASSERT_EQ(tracks.times.size(), 2u);
    EXPECT_DOUBLE_EQ(tracks.times[1], 0.04);
    for (size_t k = 0; k < 4; ++k) EXPECT_EQ(tracks.values[k], 0.0) << "frame 1 is the rest pose";
    const std::array<Vec3, 4> axes{rig[0].axes[0], rig[0].axes[1], rig[0].axes[2], rig[1].axes[0]};
    for (size_t k = 0; k < 4; ++k) {
      const double expected = drive_twist_of_matrix(m, axes[k]);
      EXPECT_NEAR(tracks.values[4 + k], expected, 1e-9) << "DOF " << k;
      largest_difference = std::max(largest_difference, std::abs(tracks.values[4 + k] - expected));
    }
    ++permutations;
  } while (std::next_permutation(order.begin(), order.end()));
  EXPECT_EQ(permutations, 6);
  std::printf("BVH rotation orders: 6 permutations x 4 DOFs, largest difference from the matrix composition %.3g deg\n",
              largest_difference);
}

TEST(BvhDrive, ASingleAxisFlexionIsTheDofValue) {
  Bvh bvh;
  std::string error;
  ASSERT_TRUE(parse_bvh(drive_bvh("RightForeArm", "Zrotation Xrotation Yrotation", "90 0 0"), &bvh, &error)) << error;
  JointTracks tracks;
  const std::vector<RigJointDofs> rig = {{"shoulder", true, {{0, 0, 1}}}, {"elbow", true, {{0, 0, 1}}}};
  ASSERT_TRUE(bvh_to_joint_tracks(bvh, rig, {{"elbow", "RightForeArm", "spec:3"}}, &tracks, &error)) << error;
  ASSERT_EQ(tracks.tracks.size(), 2u);
  EXPECT_EQ(tracks.values[2], 0.0) << "the unmapped shoulder stays at rest";
  EXPECT_NEAR(tracks.values[3], 90.0, 1e-12);
}

TEST(BvhDrive, PositionChannelsDriveTranslationDofs) {
  Bvh bvh;
  std::string error;
  ASSERT_TRUE(parse_bvh(drive_bvh("Slide", "Zrotation Xrotation Yrotation", "0 0 0"), &bvh, &error)) << error;
  JointTracks tracks;
  // The root's position channels: frame 2 is at (0, 0, 0) too; move it.
  bvh.values[6 + 0] = 2.5;
  const std::vector<RigJointDofs> rig = {{"Hips", false, {{1, 0, 0}}}};
  ASSERT_TRUE(bvh_to_joint_tracks(bvh, rig, {}, &tracks, &error)) << error;
  EXPECT_DOUBLE_EQ(tracks.values[1], 2.5);
}

TEST(BvhDrive, MappingErrorsNameTheProblem) {
  Bvh bvh;
  std::string error;
  ASSERT_TRUE(parse_bvh(drive_bvh("RightForeArm", "Zrotation Xrotation Yrotation", "90 0 0"), &bvh, &error));
  const std::vector<RigJointDofs> rig = {{"elbow", true, {{0, 0, 1}}}};
  JointTracks tracks;
  EXPECT_FALSE(bvh_to_joint_tracks(bvh, rig, {{"elbow", "LeftForeArm", "arm.toml:7: [motion.bvh_joints] elbow"}},
                                   &tracks, &error));
  EXPECT_NE(error.find("arm.toml:7"), std::string::npos) << error;
  EXPECT_NE(error.find("no joint 'LeftForeArm'"), std::string::npos) << error;
  EXPECT_FALSE(bvh_to_joint_tracks(bvh, rig, {{"knee", "RightForeArm", "arm.toml:8"}}, &tracks, &error));
  EXPECT_NE(error.find("rig has no joint 'knee'"), std::string::npos) << error;
  EXPECT_FALSE(bvh_to_joint_tracks(bvh, rig, {}, &tracks, &error)) << "no rig joint is named as a BVH joint";
  EXPECT_NE(error.find("'elbow'"), std::string::npos) << error;
  EXPECT_NE(error.find("[motion.bvh_joints]"), std::string::npos) << error;
}

TEST(BvhDrive, ANonFiniteValueIsRefusedByName) {
  for (const char* bad : {"nan", "inf", "-inf", "1e999"}) {
    Bvh bvh;
    std::string error;
    EXPECT_FALSE(
        parse_bvh(drive_bvh("RightForeArm", "Zrotation Xrotation Yrotation", std::string(bad) + " 0 0"), &bvh, &error));
    EXPECT_NE(error.find("'RightForeArm' Zrotation"), std::string::npos) << bad << ": " << error;
  }
}

}  // namespace
}  // namespace sinew::motion
