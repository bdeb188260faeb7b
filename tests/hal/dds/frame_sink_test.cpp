// sinew's own frame on DDS: a plain reader of the sinew/msg/Frame type reads
// the tick, each input's name and health bits and each stage's time as the
// frame had them.
#include "hal/dds/frame_sink.hpp"

#include <dds/dds.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "hal/dds/ros2_names.hpp"
#include "sinew/msg/Frame.h"

namespace frame_sink_test {

using namespace sinew::hal;

TEST(DdsFrame, TheRegisteredTypeIsSinewsFrame) {
  EXPECT_EQ(dds::kFrameTypeName, "sinew::msg::dds_::Frame_");
  EXPECT_EQ(dds::registered_frame_type_name(), dds::kFrameTypeName);
}

TEST(DdsFrame, TickHealthAndStageTimesArriveAsTheFrameHadThem) {
  const std::string ns = "t" + std::to_string(getpid()) + "_frame";
  dds::FrameSinkOptions o;
  o.ros_namespace = ns;
  const std::string inputs[] = {"elbow.0", "elbow.force"};
  const std::string stages[] = {"skinning", "second", "third"};
  dds::FrameSink sink;
  std::string error;
  ASSERT_TRUE(sink.open(o, inputs, stages, &error)) << error;
  const dds_entity_t participant = dds_create_participant(DDS_DOMAIN_DEFAULT, nullptr, nullptr);
  const std::string name = "rt/" + ns + "/sinew_frame";
  const dds_entity_t topic = dds_create_topic(participant, &sinew_msg_dds__Frame__desc, name.c_str(), nullptr, nullptr);
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  const dds_entity_t reader = dds_create_reader(participant, topic, qos, nullptr);
  dds_delete_qos(qos);
  ASSERT_GT(reader, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (sink.matched_readers() == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  ASSERT_GT(sink.matched_readers(), 0u);

  const int32_t values[2] = {0, 0};
  const uint8_t status[2] = {kJointStale, kJointClampedStatus | kJointMeasured};
  const uint32_t stage_ns[3] = {55000, 0, 412345};
  PoseFrame frame;
  frame.tick = 4242;
  frame.timestamp_ns = 2'000'000'001;
  frame.input_count = 2;
  frame.input_value = values;
  frame.input_status = status;
  frame.stage_count = 3;
  frame.stage_ns = stage_ns;
  ASSERT_TRUE(sink.write(frame));
  void* samples[1] = {nullptr};
  dds_sample_info_t info;
  int taken = 0;
  while (taken <= 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    samples[0] = nullptr;
    taken = dds_take(reader, samples, &info, 1, 1);
  }
  ASSERT_GT(taken, 0);
  ASSERT_TRUE(info.valid_data);
  const auto& f = *static_cast<const sinew_msg_dds__Frame_*>(samples[0]);
  EXPECT_EQ(f.tick, 4242u);
  EXPECT_EQ(f.header.stamp.sec, 2);
  EXPECT_EQ(f.header.stamp.nanosec, 1u);
  ASSERT_EQ(f.input_names._length, 2u);
  EXPECT_STREQ(f.input_names._buffer[1], "elbow.force");
  ASSERT_EQ(f.input_status._length, 2u);
  EXPECT_EQ(f.input_status._buffer[0], kJointStale);
  EXPECT_EQ(f.input_status._buffer[1], kJointClampedStatus | kJointMeasured);
  ASSERT_EQ(f.stage_names._length, 3u);
  EXPECT_STREQ(f.stage_names._buffer[2], "third");
  ASSERT_EQ(f.stage_ns._length, 3u);
  for (int s = 0; s < 3; ++s) EXPECT_EQ(f.stage_ns._buffer[s], stage_ns[s]);
  dds_return_loan(reader, samples, taken);
  dds_delete(participant);
}

}  // namespace frame_sink_test
