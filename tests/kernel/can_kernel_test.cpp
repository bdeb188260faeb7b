// SocketCAN against a real kernel's vcan0 (inside the test VM of
// scripts/kernel-test.sh): frames from can-utils (cansend, cangen) and from
// sinew's own joint-stream encoder, decoded by the SocketCAN source and the
// receiver; interface down and up again. Skips when vcan0 is absent.
#include <gtest/gtest.h>
#include <linux/can.h>
#include <net/if.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "hal/can/can_receiver.hpp"
#include "hal/can/joint_stream_decoder.hpp"
#include "hal/can/joint_stream_encoder.hpp"
#include "hal/can/kernel_frame.hpp"
#include "hal/can/socketcan_source.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/time_units.hpp"

namespace sinew::hal::can {
namespace {

constexpr const char* kVcan = "vcan0";
using sinew::test::kMs;

uint64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1'000'000'000u + static_cast<uint64_t>(ts.tv_nsec);
}

bool run(const std::string& command) {
  const int rc = std::system(command.c_str());
  if (rc != 0) std::printf("command failed (%d): %s\n", rc, command.c_str());
  return rc == 0;
}

std::string hex(const CanFrame& f) {
  char buf[16];
  std::string s;
  std::snprintf(buf, sizeof buf, f.extended ? "%08X" : "%03X", f.id);
  s += buf;
  s += f.fd ? "##0" : "#";
  for (uint8_t i = 0; i < f.len; ++i) {
    std::snprintf(buf, sizeof buf, "%02X", f.data[i]);
    s += buf;
  }
  return s;
}

// A liveness bound for frames already sent: success returns as soon as they
// are there, so only a missing frame waits it out (in a TCG guest on a loaded host).
constexpr uint64_t kLivenessNs = 30'000 * kMs;

// Drains until `want` frames arrived or kLivenessNs passed, then once more, so
// a frame beyond `want` that is already queued shows in an exact count.
// `longest_drain_ns`: the longest drain() call, preemptions included.
std::vector<CanFrame> collect(SocketCanSource& source, size_t want, uint64_t* longest_drain_ns = nullptr) {
  std::vector<CanFrame> got;
  std::array<CanFrame, 64> buf;
  const uint64_t deadline = monotonic_ns() + kLivenessNs;
  for (bool last = false; !last;) {
    last = got.size() >= want || monotonic_ns() >= deadline;
    const uint64_t start = monotonic_ns();
    const size_t n = source.drain(buf, start);
    if (longest_drain_ns != nullptr) *longest_drain_ns = std::max(*longest_drain_ns, monotonic_ns() - start);
    got.insert(got.end(), buf.begin(), buf.begin() + static_cast<long>(n));
    if (n == 0 && !last) usleep(1000);
  }
  return got;
}

class VcanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (if_nametoindex(kVcan) == 0) GTEST_SKIP() << "no vcan0 (run scripts/kernel-test.sh)";
  }
};

TEST_F(VcanTest, CansendFramesClassicExtendedAndFd) {
  SocketCanOptions options;
  options.interface = kVcan;
  options.fd = true;
  SocketCanSource source(options);
  std::string error;
  ASSERT_TRUE(source.open(monotonic_ns(), &error)) << error;
  const uint64_t before = monotonic_ns();
  ASSERT_TRUE(run("cansend vcan0 123#DEADBEEF"));
  ASSERT_TRUE(run("cansend vcan0 1ABCDE01#0102"));
  ASSERT_TRUE(run("cansend vcan0 321##1.00112233445566778899"));
  uint64_t longest_drain_ns = 0;
  const std::vector<CanFrame> got = collect(source, 3, &longest_drain_ns);
  const uint64_t after = monotonic_ns();
  ASSERT_EQ(got.size(), 3u);
  // The kernel stamps each frame as cansend sends it, between `before` and
  // `after`; drain() shifts the stamps from CLOCK_REALTIME by an offset read
  // with two clock reads inside the call, so a preempted call moves them by at
  // most its own duration: a slack measured, not assumed.
  const uint64_t slack = kMs + longest_drain_ns;  // realtime→monotonic shift: a millisecond
  EXPECT_EQ(got[0].id, 0x123u);
  EXPECT_FALSE(got[0].extended);
  EXPECT_EQ(got[0].len, 4);
  EXPECT_EQ(got[0].data[0], 0xDE);
  EXPECT_EQ(got[1].id, 0x1ABCDE01u);
  EXPECT_TRUE(got[1].extended);
  EXPECT_TRUE(got[2].fd);
  EXPECT_EQ(got[2].len, 12);  // 10 bytes padded to the next CAN FD length
  EXPECT_EQ(got[2].data[9], 0x99);
  for (const CanFrame& f : got) {
    EXPECT_GE(f.timestamp_ns + slack, before);
    EXPECT_LE(f.timestamp_ns, after + slack);
    std::printf("  cansend -> %s at +%.3f ms\n", hex(f).c_str(), static_cast<double>(f.timestamp_ns - before) / 1e6);
  }
}

TEST_F(VcanTest, CangenBurstArrivesInOrderWithMonotonicTimestamps) {
  SocketCanOptions options;
  options.interface = kVcan;
  options.receive_buffer_bytes = 1 << 20;
  SocketCanSource source(options);
  const FrameId ids[] = {{0x2A0, false}};
  ASSERT_TRUE(source.set_filters(ids, nullptr));
  ASSERT_TRUE(source.open(monotonic_ns(), nullptr));
  const int n = 500;
  ASSERT_TRUE(run("cangen vcan0 -g 0 -I 2A0 -L 8 -D i -n " + std::to_string(n)));
  ASSERT_TRUE(run("cansend vcan0 2A1#00"));  // filtered out by the kernel
  // The n frames, then one more drain: the filtered frame, sent after them,
  // would be queued by then.
  const std::vector<CanFrame> got = collect(source, static_cast<size_t>(n));
  ASSERT_EQ(got.size(), static_cast<size_t>(n));
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].id, 0x2A0u);
    EXPECT_EQ(got[i].data[0], static_cast<uint8_t>(i)) << i;  // -D i: incrementing payload
    if (i > 0) {
      EXPECT_GE(got[i].timestamp_ns, got[i - 1].timestamp_ns);
    }
  }
  std::printf("cangen: %zu frames in %.3f ms (kernel timestamps), %llu dropped\n", got.size(),
              static_cast<double>(got.back().timestamp_ns - got.front().timestamp_ns) / 1e6,
              static_cast<unsigned long long>(source.counters().dropped));
}

TEST_F(VcanTest, JointStreamFromSinewsEncoderAndFromCansend) {
  const JointStreamConfig config = default_joint_stream_config(3, false, 10 * kMs);
  JointStreamDecoder decoder;
  JointStreamSender encoder;
  std::string error;
  ASSERT_TRUE(decoder.configure(config, &error)) << error;
  ASSERT_TRUE(encoder.configure(config, &error)) << error;
  SocketCanOptions options;
  options.interface = kVcan;
  SocketCanSource source(options);
  ASSERT_TRUE(source.open(monotonic_ns(), &error)) << error;
  CanReceiver receiver;
  ASSERT_TRUE(receiver.configure(source, decoder, 64, monotonic_ns(), &error)) << error;

  // Writer: a raw socket carrying sinew's encoded frames, as the firmware's CAN output would.
  const int s = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  ASSERT_GE(s, 0);
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = static_cast<int>(if_nametoindex(kVcan));
  ASSERT_EQ(::bind(s, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  auto write_frame = [&](const CanFrame& f) {
    canfd_frame k;
    const size_t len = to_kernel(f, k);
    return len != 0 && ::write(s, &k, len) == static_cast<ssize_t>(len);
  };
  const int32_t values[3] = {1 << 28, -(1 << 29), 12345};
  for (size_t j = 0; j < 3; ++j) ASSERT_TRUE(write_frame(encoder.next(j, {&values[j], 1})));
  // The next frame of joint 0, sent by cansend from its hex dump.
  const int32_t v0 = 1 << 27;
  ASSERT_TRUE(run("cansend vcan0 " + hex(encoder.next(0, {&v0, 1}))));
  // A corrupted frame: one payload bit flipped after the CRC was computed.
  const int32_t v1 = 7;
  CanFrame bad = encoder.next(1, {&v1, 1});
  bad.data[3] ^= 0x10;
  ASSERT_TRUE(write_frame(bad));
  ::close(s);

  std::vector<JointSample> samples;
  std::vector<Rejection> rejections;
  const uint64_t deadline = monotonic_ns() + kLivenessNs;
  while ((samples.size() < 4 || rejections.empty()) && monotonic_ns() < deadline) {
    const PollResult r = receiver.poll(monotonic_ns());
    samples.insert(samples.end(), r.samples.begin(), r.samples.end());
    rejections.insert(rejections.end(), r.rejections.begin(), r.rejections.end());
    usleep(1000);
  }
  ASSERT_EQ(samples.size(), 4u);
  EXPECT_EQ(samples[0].value, values[0]);
  EXPECT_EQ(samples[1].value, values[1]);
  EXPECT_EQ(samples[2].value, values[2]);
  EXPECT_EQ(samples[3].input, 0);
  EXPECT_EQ(samples[3].value, v0);
  ASSERT_EQ(rejections.size(), 1u);
  EXPECT_EQ(rejections[0].input, 1);
  EXPECT_EQ(rejections[0].reason, RejectReason::kBadCrc);
  std::printf("joint stream over vcan0: %zu samples (3 from sinew's encoder, 1 via cansend), %zu rejected (%s)\n",
              samples.size(), rejections.size(), reject_reason_name(rejections[0].reason));
}

TEST_F(VcanTest, InterfaceDownThenUpIsReopened) {
  SocketCanOptions options;
  options.interface = kVcan;
  options.backoff = {10 * kMs, 40 * kMs};
  SocketCanSource source(options);
  ASSERT_TRUE(source.open(monotonic_ns(), nullptr));
  ASSERT_TRUE(run("ip link set vcan0 down"));
  std::array<CanFrame, 8> out;
  const uint64_t deadline = monotonic_ns() + kLivenessNs;
  while (source.bus_state() != BusState::kInterfaceDown && monotonic_ns() < deadline) {
    source.drain(out, monotonic_ns());
    usleep(1000);
  }
  EXPECT_EQ(source.bus_state(), BusState::kInterfaceDown);
  ASSERT_TRUE(run("ip link set vcan0 up"));
  const uint64_t up_deadline = monotonic_ns() + kLivenessNs;
  while (source.bus_state() != BusState::kErrorActive && monotonic_ns() < up_deadline) {
    source.drain(out, monotonic_ns());
    usleep(1000);
  }
  EXPECT_EQ(source.bus_state(), BusState::kErrorActive);
  ASSERT_TRUE(run("cansend vcan0 055#01"));
  const std::vector<CanFrame> got = collect(source, 1);
  ASSERT_EQ(got.size(), 1u);
  std::printf("down/up: %llu reopen attempts, %llu reopens, then a frame received\n",
              static_cast<unsigned long long>(source.counters().reopen_attempts),
              static_cast<unsigned long long>(source.counters().reopens));
  EXPECT_GE(source.counters().reopens, 1u);
}

}  // namespace
}  // namespace sinew::hal::can
