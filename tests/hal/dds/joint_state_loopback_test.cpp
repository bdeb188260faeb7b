// A JointState sink and source on loopback DDS, in one process: values
// arrive word for word, malformed samples are rejected whole and counted, a
// late reader gets what follows, and a publisher that goes away leaves the
// source down until one comes back. Waits are for conditions, bounded by a
// generous deadline, never for a time: they hold on a loaded machine.
#include <dds/dds.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <thread>
#include <vector>

#include "hal/common/input_health.hpp"
#include "hal/dds/joint_state_sink.hpp"
#include "hal/dds/joint_state_source.hpp"
#include "sensor_msgs/msg/JointState.h"

namespace joint_state_loopback_test {

using namespace sinew::hal;
using dds::JointChannel;
using dds::JointUnit;

const std::vector<JointChannel> kChannels = {
    {"shoulder_0", JointUnit::kRadian}, {"slide_0", JointUnit::kMetre}, {"elbow_force", JointUnit::kNewton}};

// A namespace of this process and test: parallel tests never share a topic.
std::string ns_of(const char* test) { return "t" + std::to_string(getpid()) + "_" + test; }

bool eventually(const std::function<bool()>& done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

std::unique_ptr<dds::JointStateSource> make_source(const std::string& ns) {
  dds::JointStateSourceOptions o;
  o.name = "in";
  o.ros_namespace = ns;
  o.length_exponent = -4;
  for (uint16_t k = 0; k < kChannels.size(); ++k) o.joints.push_back({kChannels[k], k});
  std::string error;
  auto s = dds::JointStateSource::create(o, &error);
  EXPECT_NE(s, nullptr) << error;
  return s;
}

std::unique_ptr<dds::JointStateSink> make_sink(const std::string& ns) {
  dds::JointStateSinkOptions o;
  o.ros_namespace = ns;
  auto sink = std::make_unique<dds::JointStateSink>();
  std::string error;
  EXPECT_TRUE(sink->open(o, kChannels, -4, &error)) << error;
  return sink;
}

struct Health {
  Health() {
    const std::vector<InputLimits> limits(kChannels.size());
    const std::vector<int32_t> rest(kChannels.size(), 0);
    health.init(limits, rest, 0);
  }
  InputHealth health;
};

PoseFrame frame_of(const int32_t* values, uint64_t tick) {
  PoseFrame f;
  f.tick = tick;
  f.timestamp_ns = tick * 1'000'000;
  f.input_count = static_cast<uint32_t>(kChannels.size());
  f.input_value = values;
  return f;
}

TEST(JointStateLoopback, EveryValueArrivesWordForWord) {
  const std::string ns = ns_of("values");
  auto source = make_source(ns);
  auto sink = make_sink(ns);
  ASSERT_TRUE(source && sink);
  ASSERT_TRUE(eventually([&] { return sink->matched_readers() > 0 && source->state() == SourceState::kOk; }));
  Health h;
  std::vector<JointSample> out(8);
  for (uint64_t t = 0; t < 50; ++t) {
    const int32_t values[3] = {static_cast<int32_t>(t * 87654321u), static_cast<int32_t>(t * 4321) - 100000,
                               static_cast<int32_t>(t << 16) - (7 << 16)};
    ASSERT_TRUE(sink->write(frame_of(values, t)));
    size_t n = 0;
    ASSERT_TRUE(eventually([&] { return (n = source->latch(UINT64_MAX, out, h.health)) > 0; })) << t;
    ASSERT_EQ(n, 3u);
    for (size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(out[k].input, k);
      EXPECT_EQ(out[k].value, values[k]) << "tick " << t << " joint " << k;
    }
  }
  EXPECT_EQ(source->counters().accepted, 50u);
  EXPECT_EQ(sink->written(), 50u);
}

// A raw ROS 2 JointState writer, as another node would publish.
struct RawWriter {
  explicit RawWriter(const std::string& ns) {
    participant = dds_create_participant(DDS_DOMAIN_DEFAULT, nullptr, nullptr);
    const std::string name = "rt/" + ns + "/joint_states";
    topic = dds_create_topic(participant, &sensor_msgs_msg_dds__JointState__desc, name.c_str(), nullptr, nullptr);
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    writer = dds_create_writer(participant, topic, qos, nullptr);
    dds_delete_qos(qos);
  }
  ~RawWriter() { dds_delete(participant); }
  void write(std::vector<const char*> names, std::vector<double> position, std::vector<double> effort = {}) {
    sensor_msgs_msg_dds__JointState_ m{};
    m.header.frame_id = const_cast<char*>("");
    m.name = {static_cast<uint32_t>(names.size()), static_cast<uint32_t>(names.size()),
              const_cast<char**>(names.data()), false};
    m.position = {static_cast<uint32_t>(position.size()), static_cast<uint32_t>(position.size()), position.data(),
                  false};
    m.effort = {static_cast<uint32_t>(effort.size()), static_cast<uint32_t>(effort.size()), effort.data(), false};
    ASSERT_EQ(dds_write(writer, &m), DDS_RETCODE_OK);
  }
  dds_entity_t participant = 0, topic = 0, writer = 0;
};

TEST(JointStateLoopback, MalformedSamplesAreRejectedWholeAndCounted) {
  const std::string ns = ns_of("malformed");
  auto source = make_source(ns);
  ASSERT_TRUE(source);
  RawWriter raw(ns);
  ASSERT_GT(raw.writer, 0);
  ASSERT_TRUE(eventually([&] { return source->state() == SourceState::kOk; }));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  raw.write({"shoulder_0", "slide_0", "elbow_force"}, {0.1, 0.2}, {0, 0, 1});        // a position short
  raw.write({"shoulder_0", "slide_0", "elbow_force"}, {0.1, 0.2, 0}, {1});           // an effort short
  raw.write({"shoulder_0", "elbow_force", "other"}, {0.1, 0.2, 0.3}, {0, 1, 0});     // slide_0 missing
  raw.write({"shoulder_0", "slide_0", "elbow_force"}, {nan, 0.2, 0}, {0, 0, 1});     // not finite
  raw.write({"shoulder_0", "slide_0", "elbow_force"}, {0.1, 9000.0, 0}, {0, 0, 1});  // beyond the rig's range
  raw.write({"extra", "elbow_force", "slide_0", "shoulder_0"}, {5, nan, 0.25, 0.5}, {0, 2, 0, 0});  // good
  ASSERT_TRUE(eventually([&] { return source->counters().samples == 6; }));
  const dds::JointStateSourceCounters c = source->counters();
  EXPECT_EQ(c.rejected_lengths, 2u);
  EXPECT_EQ(c.rejected_names, 1u);
  EXPECT_EQ(c.rejected_values, 2u);
  EXPECT_EQ(c.accepted, 1u);
  Health h;
  std::vector<JointSample> out(8);
  size_t n = 0;
  ASSERT_TRUE(eventually([&] { return (n = source->latch(UINT64_MAX, out, h.health)) > 0; }));
  ASSERT_EQ(n, 3u);  // the good sample's three joints, whatever its order and extra names
  int32_t expected = 0;
  ASSERT_TRUE(dds::joint_value_from_si(0.5, JointUnit::kRadian, -4, &expected));
  EXPECT_EQ(out[0].value, expected);
  ASSERT_TRUE(dds::joint_value_from_si(0.25, JointUnit::kMetre, -4, &expected));
  EXPECT_EQ(out[1].value, expected);
  EXPECT_EQ(out[2].value, 2 << 16);  // the force from effort, not the NaN position
}

TEST(JointStateLoopback, ALateReaderGetsWhatFollows) {
  const std::string ns = ns_of("late");
  auto sink = make_sink(ns);
  ASSERT_TRUE(sink);
  const int32_t early[3] = {1, 2, 3};
  for (uint64_t t = 0; t < 5; ++t) ASSERT_TRUE(sink->write(frame_of(early, t)));
  auto source = make_source(ns);
  ASSERT_TRUE(source);
  ASSERT_TRUE(eventually([&] { return sink->matched_readers() > 0; }));
  const int32_t later[3] = {1 << 28, 5 << 16, 9 << 16};
  ASSERT_TRUE(sink->write(frame_of(later, 5)));
  Health h;
  std::vector<JointSample> out(8);
  size_t n = 0;
  ASSERT_TRUE(eventually([&] { return (n = source->latch(UINT64_MAX, out, h.health)) > 0; }));
  ASSERT_EQ(n, 3u);
  for (size_t k = 0; k < 3; ++k) EXPECT_EQ(out[k].value, later[k]);
}

TEST(JointStateLoopback, APublisherGoneLeavesTheSourceDownUntilOneReturns) {
  const std::string ns = ns_of("gone");
  auto source = make_source(ns);
  ASSERT_TRUE(source);
  EXPECT_EQ(source->state(), SourceState::kDown);  // nobody publishes yet
  auto sink = make_sink(ns);
  ASSERT_TRUE(eventually([&] { return source->state() == SourceState::kOk; }));
  sink.reset();
  ASSERT_TRUE(eventually([&] { return source->state() == SourceState::kDown; }));
  sink = make_sink(ns);
  ASSERT_TRUE(eventually([&] { return source->state() == SourceState::kOk && sink->matched_readers() > 0; }));
  const int32_t values[3] = {11, 22, 33};
  ASSERT_TRUE(sink->write(frame_of(values, 1)));
  Health h;
  std::vector<JointSample> out(8);
  ASSERT_TRUE(eventually([&] { return source->latch(UINT64_MAX, out, h.health) == 3; }));
  EXPECT_EQ(out[2].value, 33);
}

}  // namespace joint_state_loopback_test
