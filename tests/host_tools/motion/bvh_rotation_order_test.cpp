// A hand-written skeleton with non-ZXY rotation orders, position channels on a
// child joint, a joint without channels and an End Site, checked against
// values worked out by hand.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include "host_tools/motion/bvh.hpp"
#include "host_tools/motion/bvh_pose.hpp"

namespace sinew::motion {
namespace {

constexpr const char* kSkeleton = R"(HIERARCHY
ROOT Base
{
  OFFSET 1 2 3
  CHANNELS 6 Xposition Yposition Zposition Xrotation Yrotation Zrotation
  JOINT Arm
  {
    OFFSET 0 2 0
    CHANNELS 3 Yrotation Xrotation Zrotation
    JOINT Hand
    {
      OFFSET 0 0 1
      CHANNELS 4 Zposition Zrotation Xposition Yrotation
      End Site
      {
        OFFSET 0 1 0
      }
    }
  }
  JOINT Fixed
  {
    OFFSET -1 0 0
    CHANNELS 0
  }
}
MOTION
Frames: 2
Frame Time: 0.04
0 0 0 0 0 0  0 0 0  0 0 0 0
10 20 30 90 90 0  30 45 60  0.5 90 -0.25 0
)";

using Mat3 = std::array<std::array<double, 3>, 3>;

Mat3 axis_rotation(int axis, double degrees) {
  const double r = degrees * std::numbers::pi / 180.0, c = std::cos(r), s = std::sin(r);
  if (axis == 0) return {{{1, 0, 0}, {0, c, -s}, {0, s, c}}};
  if (axis == 1) return {{{c, 0, s}, {0, 1, 0}, {-s, 0, c}}};
  return {{{c, -s, 0}, {s, c, 0}, {0, 0, 1}}};
}

Mat3 multiply(const Mat3& a, const Mat3& b) {
  Mat3 m{};
  for (size_t i = 0; i < 3; ++i)
    for (size_t j = 0; j < 3; ++j)
      for (size_t k = 0; k < 3; ++k) m[i][j] += a[i][k] * b[k][j];
  return m;
}

Mat3 matrix_of(const Quaternion& q) {
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

void expect_quaternion(const Quaternion& q, double w, double x, double y, double z) {
  EXPECT_NEAR(q.w, w, 1e-9);
  EXPECT_NEAR(q.x, x, 1e-9);
  EXPECT_NEAR(q.y, y, 1e-9);
  EXPECT_NEAR(q.z, z, 1e-9);
}

class RotationOrder : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(parse_bvh(kSkeleton, &bvh_, &error_)) << error_; }
  Bvh bvh_;
  std::string error_;
};

TEST_F(RotationOrder, ParsesTheStructure) {
  ASSERT_EQ(bvh_.joints.size(), 4u);
  EXPECT_EQ(bvh_.joints[1].name, "Arm");
  EXPECT_EQ(bvh_.joints[2].parent, 1);
  EXPECT_EQ(bvh_.joints[3].parent, 0);
  EXPECT_TRUE(bvh_.joints[3].channels.empty());
  EXPECT_EQ(bvh_.channel_count, 13u);
  EXPECT_EQ(bvh_.joints[2].first_value, 9u);
  ASSERT_EQ(bvh_.end_sites.size(), 1u);
  EXPECT_EQ(bvh_.end_sites[0].parent, 2);
  EXPECT_DOUBLE_EQ(bvh_.frame_time, 0.04);
}

// Xrotation 90, Yrotation 90 listed X then Y: R = Rx(90) * Ry(90). With
// qx = (c, s, 0, 0) and qy = (c, 0, s, 0), c = s = sqrt(1/2):
// qx * qy = (c*c, c*s, s*c, s*s) = (1/2, 1/2, 1/2, 1/2), the 120 degree turn
// about (1,1,1) that takes x to y. (Y then X would give z = -1/2.)
TEST_F(RotationOrder, RootXYZIsRxTimesRy) {
  expect_quaternion(local_rotation(bvh_, 0, 1), 0.5, 0.5, 0.5, 0.5);
  const Vec3 t = local_translation(bvh_, 0, 1);
  EXPECT_DOUBLE_EQ(t[0], 11);
  EXPECT_DOUBLE_EQ(t[1], 22);
  EXPECT_DOUBLE_EQ(t[2], 33);
}

// Y 30, X 45, Z 60 listed Y X Z: q = qy(30) * qx(45) * qz(60), expanded by hand
// from the half-angle quaternions (cos 15, 0, sin 15, 0), (cos 22.5, sin 22.5, 0, 0),
// (cos 30, 0, 0, sin 30).
TEST_F(RotationOrder, ArmYXZIsRyRxRz) {
  const Quaternion q = local_rotation(bvh_, 1, 1);
  expect_quaternion(q, 0.822363171906, 0.439679739541, 0.022260026715, 0.360423405650);
  // The same rotation as a product of matrices.
  const Mat3 expected = multiply(multiply(axis_rotation(1, 30), axis_rotation(0, 45)), axis_rotation(2, 60));
  const Mat3 actual = matrix_of(q);
  for (size_t i = 0; i < 3; ++i)
    for (size_t j = 0; j < 3; ++j) EXPECT_NEAR(actual[i][j], expected[i][j], 1e-12) << i << "," << j;
}

TEST_F(RotationOrder, HandMixesPositionAndRotationChannels) {
  // Zrotation 90 then Yrotation 0: qz(90).
  expect_quaternion(local_rotation(bvh_, 2, 1), std::sqrt(0.5), 0, 0, std::sqrt(0.5));
  const Vec3 t = local_translation(bvh_, 2, 1);  // OFFSET (0, 0, 1) + Xposition -0.25, Zposition 0.5
  EXPECT_DOUBLE_EQ(t[0], -0.25);
  EXPECT_DOUBLE_EQ(t[1], 0);
  EXPECT_DOUBLE_EQ(t[2], 1.5);
}

TEST_F(RotationOrder, ZeroFrameIsIdentity) {
  for (size_t j = 0; j < bvh_.joints.size(); ++j) expect_quaternion(local_rotation(bvh_, j, 0), 1, 0, 0, 0);
}

TEST_F(RotationOrder, GlobalPositionsFollowTheParentRotation) {
  // The root turns x->y, y->z, z->x, so Arm's OFFSET (0, 2, 0) becomes (0, 0, 2).
  const std::vector<Vec3> p = global_positions(bvh_, 1);
  EXPECT_NEAR(p[1][0], 11, 1e-12);
  EXPECT_NEAR(p[1][1], 22, 1e-12);
  EXPECT_NEAR(p[1][2], 35, 1e-12);
  // Fixed's OFFSET (-1, 0, 0) becomes (0, -1, 0).
  EXPECT_NEAR(p[3][0], 11, 1e-12);
  EXPECT_NEAR(p[3][1], 21, 1e-12);
  EXPECT_NEAR(p[3][2], 33, 1e-12);
}

TEST_F(RotationOrder, RestPose) {
  const std::vector<Vec3> rest = rest_global_positions(bvh_);
  const std::vector<Vec3> expected = {{1, 2, 3}, {1, 4, 3}, {1, 4, 4}, {0, 2, 3}};
  EXPECT_EQ(rest, expected);
  const std::vector<Vec3> tips = rest_end_site_positions(bvh_);
  ASSERT_EQ(tips.size(), 1u);
  EXPECT_EQ(tips[0], (Vec3{1, 5, 4}));
}

TEST_F(RotationOrder, IndicesOutOfRangeThrow) {
  EXPECT_THROW(local_rotation(bvh_, 4, 0), std::out_of_range);
  EXPECT_THROW(local_rotation(bvh_, 0, 2), std::out_of_range);
  EXPECT_THROW(global_positions(bvh_, 2), std::out_of_range);
}

}  // namespace
}  // namespace sinew::motion
