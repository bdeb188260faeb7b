// The pose payload shared by the log and the UDP stream.
#include "hal/output/pose_codec.hpp"

#include <vector>

#include "hal/output/le_bytes.hpp"
#include "hal/output/pose_decode.hpp"
#include "test_poses.hpp"

namespace sinew::test {
namespace {

using namespace hal::output;
using hal::PoseFrame;

TEST(PoseCodec, RoundTripsWithAndWithoutNormals) {
  for (const bool normals : {false, true}) {
    TestPose pose(17, 5, normals, -7);
    pose.set_tick(42);
    std::vector<uint8_t> bytes(max_pose_payload_bytes(pose.shape()));
    const size_t n = encode_pose(pose.frame(), pose.shape(), bytes);
    ASSERT_EQ(n, bytes.size());
    EXPECT_EQ(n, kPoseHeaderBytes + (normals ? 24u : 12u) * 17 + 5u * 5);
    DecodedPose got;
    std::string why;
    ASSERT_TRUE(decode_pose(bytes, &got, &why)) << why;
    expect_same_pose(got, pose.frame(), normals);
  }
}

TEST(PoseCodec, LayoutIsLittleEndianStructOfArrays) {
  TestPose pose(2, 1, false, 3);
  pose.set_tick(9);
  std::vector<uint8_t> bytes(max_pose_payload_bytes(pose.shape()));
  ASSERT_EQ(encode_pose(pose.frame(), pose.shape(), bytes), bytes.size());
  const PoseFrame& f = pose.frame();
  EXPECT_EQ(load_u64(&bytes[0]), 9u);
  EXPECT_EQ(load_u64(&bytes[8]), f.timestamp_ns);
  EXPECT_EQ(load_i32(&bytes[16]), 3);
  EXPECT_EQ(load_u32(&bytes[20]), 2u);
  EXPECT_EQ(load_u32(&bytes[24]), 1u);
  EXPECT_EQ(load_u32(&bytes[28]), 0u);
  EXPECT_EQ(load_i32(&bytes[32]), f.position[0][0]);
  EXPECT_EQ(load_i32(&bytes[36]), f.position[0][1]);
  EXPECT_EQ(load_i32(&bytes[40]), f.position[1][0]);
  EXPECT_EQ(load_i32(&bytes[52]), f.position[2][1]);
  EXPECT_EQ(load_i32(&bytes[56]), f.input_value[0]);
  EXPECT_EQ(bytes[60], f.input_status[0]);
}

TEST(PoseCodec, NormalsAreDroppedWhenTheShapeHasNone) {
  TestPose pose(4, 2, true);
  FrameShape shape = pose.shape();
  shape.normals = false;
  std::vector<uint8_t> bytes(max_pose_payload_bytes(shape));
  ASSERT_EQ(encode_pose(pose.frame(), shape, bytes), bytes.size());
  DecodedPose got;
  std::string why;
  ASSERT_TRUE(decode_pose(bytes, &got, &why)) << why;
  EXPECT_FALSE(got.has_normals);
}

TEST(PoseCodec, RefusesMismatchesAndShortBuffers) {
  TestPose pose(4, 2, false);
  std::vector<uint8_t> bytes(max_pose_payload_bytes(pose.shape()));
  FrameShape other = pose.shape();
  other.length_exponent += 1;
  EXPECT_EQ(encode_pose(pose.frame(), other, bytes), 0u);
  EXPECT_EQ(encode_pose(pose.frame(), pose.shape(), std::span<uint8_t>(bytes).first(bytes.size() - 1)), 0u);
  PoseFrame missing = pose.frame();
  missing.position[1] = nullptr;
  EXPECT_EQ(encode_pose(missing, pose.shape(), bytes), 0u);
}

TEST(PoseCodec, DecodeRefusesWrongSizes) {
  TestPose pose(4, 2, false);
  std::vector<uint8_t> bytes(max_pose_payload_bytes(pose.shape()));
  encode_pose(pose.frame(), pose.shape(), bytes);
  DecodedPose got;
  std::string why;
  EXPECT_FALSE(decode_pose(std::span<const uint8_t>(bytes).first(bytes.size() - 1), &got, &why));
  bytes.push_back(0);
  EXPECT_FALSE(decode_pose(bytes, &got, &why));
  EXPECT_FALSE(decode_pose(std::span<const uint8_t>(bytes).first(10), &got, &why));
}

}  // namespace
}  // namespace sinew::test
