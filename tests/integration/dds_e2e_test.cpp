// Two daemons on loopback DDS (docs/ros2.md): one publishes its rig's
// applied inputs as ROS 2 JointState, the other reads them as its inputs.
// The consumer applies exactly the publisher's values (the transport is
// exact), its pose is the publisher's pose for them, its inputs go stale
// when the publisher is killed and recover when a publisher returns. Every
// wait is for a condition in the daemons' output, bounded by a generous
// deadline; no assertion is on a time.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "tests/integration/daemon_harness.hpp"

namespace dds_e2e_test {

using Clock = std::chrono::steady_clock;

bool eventually(const std::function<bool()>& done) {
  const auto deadline = Clock::now() + std::chrono::seconds(90);
  while (!done()) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

// The last "N samples" the consumer's dds source reported, or 0.
uint64_t samples_reported(const std::string& out) {
  static const std::regex re("publishers, ([0-9]+) samples");
  uint64_t last = 0;
  for (auto it = std::sregex_iterator(out.begin(), out.end(), re); it != std::sregex_iterator(); ++it)
    last = std::stoull((*it)[1]);
  return last;
}

std::string write_config(const std::string& name, const std::string& body) {
  const std::string path = testing::TempDir() + "/" + name + ".toml";
  std::ofstream(path) << "[rig]\nbuiltin = \"arm\"\n" << body;
  return path;
}

TEST(DdsEndToEnd, ASecondDaemonAppliesTheFirstsAnglesAndFollowsItsPose) {
  const std::string ns = "e2e_" + std::to_string(getpid());
  const std::string dir = testing::TempDir();
  const std::string consumer_log = dir + "/dds_consumer.log", consumer_out = dir + "/dds_consumer.out";
  const std::string consumer =
      write_config("dds_consumer",
                   "[loop]\nrate_hz = 100\nduration_s = 0\nstats_interval_s = 0.2\nstep_budget = 0\n"
                   "[[source]]\ntype = \"dds\"\nnamespace = \"" +
                       ns +
                       "\"\n"
                       "[[sink]]\ntype = \"log\"\npath = \"" +
                       consumer_log + "\"\n");
  const auto publisher = [&](const std::string& name) {
    return write_config(name,
                        "[loop]\nrate_hz = 50\nduration_s = 0\nstats_interval_s = 0\nstep_budget = 0\n"
                        "[[source]]\ntype = \"trajectory\"\nperiod_ms = 20\n"
                        "[[sink]]\ntype = \"dds\"\nnamespace = \"" +
                            ns +
                            "\"\n"
                            "[[sink]]\ntype = \"log\"\npath = \"" +
                            dir + "/" + name + ".log\"\n");
  };
  // A frame log sink appends to an existing log, and the waits below read
  // the daemons' output files: start from none (an earlier run's output
  // would satisfy a wait before this run's daemon has written anything).
  for (const std::string& file : {consumer_log, consumer_out, dir + "/dds_pub1.log", dir + "/dds_pub2.log",
                                  dir + "/dds_pub1.out", dir + "/dds_pub2.out"})
    std::remove(file.c_str());
  sinew::test::BackgroundDaemon b(consumer, consumer_out);
  ASSERT_TRUE(b.started());
  ASSERT_TRUE(eventually([&] { return sinew::test::slurp(consumer_out).find("running:") != std::string::npos; }))
      << sinew::test::slurp(consumer_out);

  // The first publisher, until the consumer has taken a few dozen samples; then killed.
  {
    sinew::test::BackgroundDaemon a(publisher("dds_pub1"), dir + "/dds_pub1.out");
    ASSERT_TRUE(eventually([&] { return samples_reported(sinew::test::slurp(consumer_out)) >= 30; }))
        << sinew::test::slurp(consumer_out) << sinew::test::slurp(dir + "/dds_pub1.out");
    a.kill();
  }
  const size_t killed_at = sinew::test::slurp(consumer_out).size();
  ASSERT_TRUE(eventually([&] {
    return sinew::test::slurp(consumer_out).find("inputs stale 8/8", killed_at) != std::string::npos;
  })) << sinew::test::slurp(consumer_out);
  const uint64_t before_restart = samples_reported(sinew::test::slurp(consumer_out));

  // A publisher again: the consumer's inputs recover.
  {
    sinew::test::BackgroundDaemon a(publisher("dds_pub2"), dir + "/dds_pub2.out");
    ASSERT_TRUE(eventually([&] { return samples_reported(sinew::test::slurp(consumer_out)) >= before_restart + 30; }))
        << sinew::test::slurp(consumer_out);
    EXPECT_EQ(a.stop(), 0);
  }
  // The publisher's skin as a ROS 2 Marker, 30 Hz from a 50 Hz tick: every 2nd frame.
  const std::string pub2_out = sinew::test::slurp(dir + "/dds_pub2.out");
  EXPECT_NE(pub2_out.find("publishes visualization_msgs/msg/Marker"), std::string::npos) << pub2_out;
  EXPECT_NE(pub2_out.find("every 2 ticks"), std::string::npos) << pub2_out;
  std::smatch meshes;
  ASSERT_TRUE(std::regex_search(pub2_out, meshes, std::regex("triangles\\): ([0-9]+) written, 0 failed"))) << pub2_out;
  EXPECT_GT(std::stoull(meshes[1]), 0u);
  EXPECT_EQ(b.stop(), 0) << sinew::test::slurp(consumer_out);

  // Every input vector the publishers applied, with the pose it gave.
  std::map<std::vector<int32_t>, const sinew::hal::output::DecodedPose*> published;
  const sinew::test::FrameLog pub1 = sinew::test::read_frame_log(dir + "/dds_pub1.log");
  const sinew::test::FrameLog pub2 = sinew::test::read_frame_log(dir + "/dds_pub2.log");
  for (const auto* log : {&pub1, &pub2})
    for (const auto& pose : log->poses) published.emplace(pose.input_value, &pose);
  ASSERT_FALSE(published.empty());

  const sinew::test::FrameLog got = sinew::test::read_frame_log(consumer_log);
  ASSERT_FALSE(got.poses.empty());
  constexpr uint8_t kStale = 1u << 1;  // hal::kJointStale
  // The first publisher was killed: the frames its log sink still had
  // queued were never written, though its DDS sink (another I/O thread) may
  // have published them. So the samples the consumer took last before its
  // inputs went stale may be missing from that log: one run of them, ended
  // by stale inputs, never by a logged sample. Stale frames before the first
  // sample (a publisher slow to start) and between samples (a loaded
  // publisher late by more than the timeout) are not the kill; the second
  // publisher stopped cleanly, so each of its samples is in its log.
  size_t applied = 0, stale_after_samples = 0, recovered = 0, unlogged = 0, unlogged_runs = 0;
  bool seen_sample = false, unlogged_run_open = false;
  for (size_t i = 1; i < got.poses.size(); ++i) {
    const auto& pose = got.poses[i];
    const bool stale = pose.input_status[0] & kStale;
    if (stale) {
      stale_after_samples += seen_sample;
      unlogged_run_open = false;
      continue;
    }
    if (pose.input_value == got.poses[i - 1].input_value) continue;
    seen_sample = true;
    // A new sample: exactly one of the publishers' input vectors ...
    const auto it = published.find(pose.input_value);
    if (it == published.end()) {
      ++unlogged;
      unlogged_runs += unlogged_run_open ? 0 : 1;
      unlogged_run_open = true;
      continue;
    }
    ASSERT_FALSE(unlogged_run_open) << "consumer tick " << pose.tick
                                    << " applied a logged sample right after inputs no publisher logged";
    ++applied;
    if (stale_after_samples > 0) ++recovered;
    // ... and the publisher's pose for it, word for word (skinning alone is
    // a function of the inputs).
    for (int c = 0; c < 3; ++c) ASSERT_EQ(pose.position[c], it->second->position[c]) << "tick " << pose.tick;
  }
  for (const std::string& log : {consumer_log, dir + "/dds_pub1.log", dir + "/dds_pub2.log"}) std::remove(log.c_str());
  // At most the killed publisher's log queue (sink_ring_frames, 128 by default).
  EXPECT_LE(unlogged, 128u);
  EXPECT_LE(unlogged_runs, 1u);  // one kill
  EXPECT_GE(applied, 10u);  // of the 60 or more samples taken: a loaded consumer may apply only the latest of several
  EXPECT_GT(stale_after_samples, 0u);  // the kill left the inputs stale ...
  EXPECT_GT(recovered, 0u);            // ... and the second publisher's samples were applied after
}

}  // namespace dds_e2e_test
