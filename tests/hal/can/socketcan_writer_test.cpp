// The SocketCAN sender (hal/can/socketcan_writer.hpp). With a vcan0
// interface (the real-kernel VM, scripts/kernel-test.sh) its frames must
// arrive at a SocketCanSource on the same bus, in order and unchanged;
// without one that test skips. A missing interface is tested everywhere.
#include "hal/can/socketcan_writer.hpp"

#include <gtest/gtest.h>
#include <net/if.h>
#include <time.h>
#include <unistd.h>

#include <array>
#include <vector>

#include "hal/can/socketcan_source.hpp"

namespace sinew::hal::can {
namespace {

uint64_t writer_test_now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1'000'000'000u + static_cast<uint64_t>(ts.tv_nsec);
}

CanFrame joint_like(uint32_t id, uint8_t first) {
  CanFrame f;
  f.id = id;
  f.len = 8;
  for (uint8_t i = 0; i < 8; ++i) f.data[i] = static_cast<uint8_t>(first + i);
  return f;
}

TEST(SocketCanWriter, MissingInterfaceIsRefusedThenDropsAndRetriesWithBackoff) {
  const uint64_t ms = 1'000'000;
  SocketCanWriterOptions options;
  options.interface = "sinewnone0";
  options.backoff = {100 * ms, 400 * ms};
  SocketCanWriter writer(options);
  std::string error;
  EXPECT_FALSE(writer.open(&error));
  EXPECT_NE(error.find("CAN interface sinewnone0"), std::string::npos) << error;
  EXPECT_LT(writer.fd(), 0);
  const std::array<CanFrame, 3> frames = {joint_like(0x300, 0), joint_like(0x300, 8), joint_like(0x300, 16)};
  EXPECT_EQ(writer.send(frames, 1000 * ms), 0u);
  EXPECT_EQ(writer.send(frames, 1050 * ms), 0u);
  EXPECT_EQ(writer.frames_sent(), 0u);
  EXPECT_EQ(writer.frames_dropped(), 6u);
  EXPECT_NE(writer.status_line().find("down"), std::string::npos) << writer.status_line();
}

TEST(SocketCanWriter, FramesArriveOnTheBusInOrderAndUnchanged) {
  if (if_nametoindex("vcan0") == 0)
    GTEST_SKIP() << "no vcan0 interface here (modprobe vcan; ip link add vcan0 type vcan; ip link set vcan0 up)";
  SocketCanOptions listen;
  listen.interface = "vcan0";
  SocketCanSource source(listen);
  std::string error;
  ASSERT_TRUE(source.open(writer_test_now_ns(), &error)) << error;
  SocketCanWriterOptions options;
  options.interface = "vcan0";
  SocketCanWriter writer(options);
  ASSERT_TRUE(writer.open(&error)) << error;
  std::vector<CanFrame> sent;
  for (uint8_t i = 0; i < 12; ++i) sent.push_back(joint_like(i % 2 == 0 ? 0x300 : 0x1ABCDE, i));
  sent[1].extended = true;
  for (size_t i = 3; i < sent.size(); i += 2) sent[i].extended = true;
  ASSERT_EQ(writer.send(sent, writer_test_now_ns()), sent.size()) << writer.status_line();
  std::array<CanFrame, 32> out;
  size_t got = 0;
  // A liveness bound: success returns as soon as the frames are in.
  for (const uint64_t deadline = writer_test_now_ns() + 30'000'000'000u;
       got < sent.size() && writer_test_now_ns() < deadline;) {
    const size_t n = source.drain(std::span<CanFrame>(out).subspan(got), writer_test_now_ns());
    got += n;
    if (n == 0) usleep(1000);
  }
  ASSERT_EQ(got, sent.size());
  for (size_t i = 0; i < got; ++i) {
    EXPECT_EQ(out[i].id, sent[i].id) << i;
    EXPECT_EQ(out[i].extended, sent[i].extended) << i;
    EXPECT_EQ(out[i].len, 8u) << i;
    for (size_t b = 0; b < 8; ++b) EXPECT_EQ(out[i].data[b], sent[i].data[b]) << i;
  }
  EXPECT_EQ(writer.frames_sent(), sent.size());
  EXPECT_EQ(writer.frames_dropped(), 0u);
}

}  // namespace
}  // namespace sinew::hal::can
