// Compact per-joint CAN frames.
#include "hal/output/can_frames.hpp"

#include <vector>

#include "test_poses.hpp"
#include "tests/support/alloc_guard.hpp"

namespace sinew::test {
namespace {

using namespace hal::output;
using hal::PoseFrame;

TEST(CanFrames, OneFramePerInputWithTheDocumentedLayout) {
  TestPose pose(0, 3, false);
  pose.set_tick(0x123);
  std::vector<int32_t> values = {-1, 0x12345678, INT32_MIN};
  std::vector<uint8_t> status = {hal::kJointOk, hal::kJointStale | hal::kJointRejected, hal::kJointClampedStatus};
  PoseFrame f = pose.frame();
  f.input_value = values.data();
  f.input_status = status.data();

  CanFrameEncoder encoder;
  std::string error;
  ASSERT_TRUE(encoder.configure({0x2A0, false}, &error)) << error;
  std::vector<can_frame> out(4);
  ASSERT_EQ(encoder.encode(f, out), 3u);
  const can_frame& c = out[1];
  EXPECT_EQ(c.can_id, 0x2A0u);
  EXPECT_EQ(c.len, 8u);
  const uint8_t want[8] = {0x01, 0x00, 0x78, 0x56, 0x34, 0x12, 0x06, 0x03};
  for (int i = 0; i < 8; ++i) EXPECT_EQ(c.data[i], want[i]) << "byte " << i;

  for (uint32_t i = 0; i < 3; ++i) {
    CanJointFrame j;
    ASSERT_TRUE(decode_can_joint_frame(out[i], &j));
    EXPECT_EQ(j.input, i);
    EXPECT_EQ(j.value, values[i]);
    EXPECT_EQ(j.status, status[i]);
    EXPECT_EQ(j.counter, 0x3);
  }
}

TEST(CanFrames, CounterIsTheTickModuloSixteen) {
  TestPose pose(0, 1, false);
  CanFrameEncoder encoder;
  std::string error;
  ASSERT_TRUE(encoder.configure({}, &error));
  can_frame out[1];
  for (uint64_t t = 0; t < 40; ++t) {
    pose.set_tick(t);
    ASSERT_EQ(encoder.encode(pose.frame(), out), 1u);
    CanJointFrame j;
    ASSERT_TRUE(decode_can_joint_frame(out[0], &j));
    EXPECT_EQ(j.counter, t % 16);
  }
}

TEST(CanFrames, IdentifierFormats) {
  CanFrameEncoder encoder;
  std::string error;
  EXPECT_FALSE(encoder.configure({0x800, false}, &error));
  EXPECT_NE(error.find("11 bits"), std::string::npos) << error;
  EXPECT_FALSE(encoder.configure({0x20000000, true}, &error));
  ASSERT_TRUE(encoder.configure({0x1ABCDEF0, true}, &error));
  TestPose pose(0, 1, false);
  can_frame out[1];
  ASSERT_EQ(encoder.encode(pose.frame(), out), 1u);
  EXPECT_EQ(out[0].can_id, 0x1ABCDEF0u | CAN_EFF_FLAG);
}

TEST(CanFrames, TooSmallABufferGivesNoFrames) {
  TestPose pose(0, 5, false);
  CanFrameEncoder encoder;
  std::string error;
  ASSERT_TRUE(encoder.configure({}, &error));
  std::vector<can_frame> out(4);
  EXPECT_EQ(encoder.encode(pose.frame(), out), 0u);
}

TEST(CanFrames, DecodeRefusesOtherFrames) {
  can_frame f{};
  f.len = 8;
  f.data[7] = 0x10;  // reserved bits set
  CanJointFrame j;
  EXPECT_FALSE(decode_can_joint_frame(f, &j));
  f.data[7] = 0;
  f.len = 6;
  EXPECT_FALSE(decode_can_joint_frame(f, &j));
}

TEST(CanFrames, EncodingDoesNotAllocate) {
  TestPose pose(0, 64, false);
  CanFrameEncoder encoder;
  std::string error;
  ASSERT_TRUE(encoder.configure({}, &error));
  std::vector<can_frame> out(64);
  AllocationCounter counter;
  size_t total = 0;
  for (uint64_t t = 0; t < 100; ++t) {
    pose.set_tick(t);
    total += encoder.encode(pose.frame(), out);
  }
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_EQ(total, 6400u);
}

}  // namespace
}  // namespace sinew::test
