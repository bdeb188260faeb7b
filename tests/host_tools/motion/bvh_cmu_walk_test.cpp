// The real CMU walk (tests/data/cmu_walk.bvh, see tests/data/ATTRIBUTION.md):
// its counts must match what its provenance record states.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "host_tools/motion/bvh.hpp"
#include "host_tools/motion/bvh_pose.hpp"

namespace sinew::motion {
namespace {

const std::string kWalkPath = std::string(SINEW_TEST_DATA_DIR) + "/cmu_walk.bvh";

class CmuWalk : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(load_bvh(kWalkPath, &bvh_, &error_)) << error_; }
  Bvh bvh_;
  std::string error_;
};

TEST_F(CmuWalk, CountsMatchTheRecordedProvenance) {
  EXPECT_EQ(bvh_.joints.size(), 31u);
  EXPECT_EQ(bvh_.end_sites.size(), 7u);
  EXPECT_EQ(bvh_.channel_count, 96u);
  EXPECT_EQ(bvh_.frame_count, 344u);
  EXPECT_DOUBLE_EQ(bvh_.frame_time, 0.0083333);
  EXPECT_EQ(bvh_.values.size(), 344u * 96u);
}

TEST_F(CmuWalk, SkeletonNamesAndChannelOrders) {
  ASSERT_EQ(bvh_.joints[0].name, "Hips");
  EXPECT_EQ(bvh_.joints[0].parent, -1);
  const std::vector<BvhChannel> root = {BvhChannel::kXposition, BvhChannel::kYposition, BvhChannel::kZposition,
                                        BvhChannel::kZrotation, BvhChannel::kYrotation, BvhChannel::kXrotation};
  EXPECT_EQ(bvh_.joints[0].channels, root);
  const std::vector<BvhChannel> zyx = {BvhChannel::kZrotation, BvhChannel::kYrotation, BvhChannel::kXrotation};
  for (size_t j = 1; j < bvh_.joints.size(); ++j) {
    EXPECT_EQ(bvh_.joints[j].channels, zyx) << bvh_.joints[j].name;
    EXPECT_LT(bvh_.joints[j].parent, static_cast<int>(j)) << "parents precede children";
    EXPECT_EQ(bvh_.joints[j].first_value, 6 + 3 * (j - 1));
  }
  for (const char* name : {"LHipJoint", "LeftUpLeg", "LeftToeBase", "LowerBack", "Spine1", "Neck1", "Head",
                           "LeftForeArm", "LeftHandIndex1", "LThumb", "RightForeArm", "RThumb"})
    EXPECT_GE(bvh_.find_joint(name), 0) << name;
  EXPECT_EQ(bvh_.joints[static_cast<size_t>(bvh_.find_joint("LeftUpLeg"))].name, "LeftUpLeg");
  EXPECT_EQ(bvh_.find_joint("LeftUpLeg"), 2);
  EXPECT_EQ(bvh_.joints[2].parent, 1);
}

TEST_F(CmuWalk, FirstAndLastRowsAreTheFilesValues) {
  // First values of the first row and last values of the last row, as written in the file.
  const auto first = bvh_.frame(0);
  const auto last = bvh_.frame(bvh_.frame_count - 1);
  EXPECT_DOUBLE_EQ(last[93], 4.9884);
  EXPECT_DOUBLE_EQ(last[94], -16.5109);
  EXPECT_DOUBLE_EQ(last[95], 3.3779);
  EXPECT_EQ(first.size(), 96u);
}

TEST_F(CmuWalk, RootWalksAboutSixtyUnitsAlongPlusZ) {
  const std::vector<Vec3> start = global_positions(bvh_, 0);
  const std::vector<Vec3> end = global_positions(bvh_, bvh_.frame_count - 1);
  const double dz = end[0][2] - start[0][2];
  EXPECT_GT(dz, 50.0);
  EXPECT_LT(dz, 70.0);
  EXPECT_LT(std::abs(end[0][0] - start[0][0]), 0.2 * dz) << "a straight walk";
}

TEST_F(CmuWalk, RestPoseIsTheSumOfOffsets) {
  const std::vector<Vec3> rest = rest_global_positions(bvh_);
  ASSERT_EQ(rest.size(), bvh_.joints.size());
  for (size_t j = 0; j < rest.size(); ++j) {
    const BvhJoint& joint = bvh_.joints[j];
    Vec3 expected = joint.offset;
    if (joint.parent >= 0)
      for (size_t a = 0; a < 3; ++a) expected[a] += rest[static_cast<size_t>(joint.parent)][a];
    for (size_t a = 0; a < 3; ++a) EXPECT_DOUBLE_EQ(rest[j][a], expected[a]) << joint.name;
  }
  // LeftUpLeg: Hips (0,0,0) + LHipJoint (0,0,0) + its own OFFSET.
  const Vec3& left_up_leg = rest[2];
  EXPECT_DOUBLE_EQ(left_up_leg[0], 1.65674);
  EXPECT_DOUBLE_EQ(left_up_leg[1], -1.80282);
  EXPECT_DOUBLE_EQ(left_up_leg[2], 0.62477);
}

TEST_F(CmuWalk, EveryLocalRotationIsUnit) {
  for (size_t f = 0; f < bvh_.frame_count; f += 17) {
    for (size_t j = 0; j < bvh_.joints.size(); ++j) {
      const Quaternion q = local_rotation(bvh_, j, f);
      EXPECT_NEAR(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z, 1.0, 1e-12);
    }
  }
}

}  // namespace
}  // namespace sinew::motion
