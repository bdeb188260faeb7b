// The real SocketCAN backend. Needs a vcan0 interface (modprobe vcan;
// ip link add vcan0 type vcan; ip link set vcan0 up); without it the tests
// that need traffic skip. Opening a missing interface is tested everywhere.
#include "hal/can/socketcan_source.hpp"

#include <gtest/gtest.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <span>

#include "hal/can/joint_stream_encoder.hpp"
#include "hal/can/kernel_frame.hpp"
#include "tests/support/alloc_guard.hpp"

namespace sinew::hal::can {
namespace {

constexpr const char* kVcan = "vcan0";

uint64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1'000'000'000u + static_cast<uint64_t>(ts.tv_nsec);
}

bool vcan_present() { return if_nametoindex(kVcan) != 0; }

struct Drained {
  size_t frames = 0;
  uint64_t longest_drain_ns = 0;  // the longest drain() call, preemptions included
};

// Drains into `out` until `want` frames have arrived (30 s: a liveness bound,
// success returns at once), then once more: a frame beyond them fails the
// caller's exact count. `out` must have room for more than `want`.
Drained drain_expecting(SocketCanSource& source, std::span<CanFrame> out, size_t want) {
  Drained d;
  const uint64_t deadline = monotonic_ns() + 30'000'000'000u;
  for (bool last = false; !last;) {
    last = d.frames >= want || monotonic_ns() >= deadline;
    const uint64_t start = monotonic_ns();
    const size_t got = source.drain(out.subspan(d.frames), start);
    d.longest_drain_ns = std::max(d.longest_drain_ns, monotonic_ns() - start);
    d.frames += got;
    if (got == 0 && !last) usleep(1000);
  }
  return d;
}

constexpr const char* kNoVcan =
    "no vcan0 interface here (needs the vcan module: modprobe vcan; ip link add vcan0 type vcan; "
    "ip link set vcan0 up)";

// A second raw socket playing the sender, as cansend does.
class Sender {
 public:
  explicit Sender(bool fd) {
    s_ = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
    const int one = 1;
    if (fd) ::setsockopt(s_, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &one, sizeof one);
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = static_cast<int>(if_nametoindex(kVcan));
    ::bind(s_, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  }
  ~Sender() { ::close(s_); }
  bool send(const CanFrame& f) {
    canfd_frame k;
    const size_t n = to_kernel(f, k);
    return n != 0 && ::write(s_, &k, n) == static_cast<ssize_t>(n);
  }

 private:
  int s_ = -1;
};

TEST(SocketCanSource, MissingInterfaceIsDownAndRetriedWithBackoff) {
  const uint64_t ms = 1'000'000;
  SocketCanOptions options;
  options.interface = "sinewnone0";
  options.backoff = {100 * ms, 400 * ms};
  SocketCanSource source(options);
  std::string error;
  EXPECT_FALSE(source.open(1000 * ms, &error));
  EXPECT_FALSE(error.empty());  // e.g. no such device, or no CAN support in this kernel
  EXPECT_EQ(source.bus_state(), BusState::kInterfaceDown);
  EXPECT_LT(source.fd(), 0);
  std::array<CanFrame, 4> out;
  EXPECT_EQ(source.drain(out, 1050 * ms), 0u);
  EXPECT_EQ(source.counters().reopen_attempts, 0u);
  EXPECT_EQ(source.drain(out, 1100 * ms), 0u);
  EXPECT_EQ(source.counters().reopen_attempts, 1u);
  EXPECT_EQ(source.drain(out, 1299 * ms), 0u);
  EXPECT_EQ(source.counters().reopen_attempts, 1u);
  EXPECT_EQ(source.drain(out, 1300 * ms), 0u);
  EXPECT_EQ(source.counters().reopen_attempts, 2u);
  EXPECT_EQ(source.bus_state(), BusState::kInterfaceDown);
}

TEST(SocketCanSource, OverlongInterfaceNameIsRefused) {
  SocketCanOptions options;
  options.interface = "an-interface-name-too-long";
  SocketCanSource source(options);
  std::string error;
  EXPECT_FALSE(source.open(0, &error));
  EXPECT_NE(error.find("interface name"), std::string::npos) << error;
}

TEST(SocketCanSource, ReceivesFramesWithMonotonicKernelTimestamps) {
  if (!vcan_present()) GTEST_SKIP() << kNoVcan;
  SocketCanOptions options;
  options.interface = kVcan;
  SocketCanSource source(options);
  std::string error;
  ASSERT_TRUE(source.open(monotonic_ns(), &error)) << error;
  EXPECT_EQ(source.bus_state(), BusState::kErrorActive);
  Sender sender(false);
  const uint64_t before = monotonic_ns();
  for (uint8_t i = 0; i < 5; ++i) {
    const uint8_t data[2] = {i, 0xAA};
    ASSERT_TRUE(sender.send(make_data_frame(0x123, false, data, 2)));
  }
  std::array<CanFrame, 16> out;
  const Drained drained = drain_expecting(source, out, 5);
  const uint64_t after = monotonic_ns();
  const size_t n = drained.frames;
  ASSERT_EQ(n, 5u);
  // The kernel stamps each frame as it is sent, between `before` and `after`.
  // drain() shifts the stamps from CLOCK_REALTIME by an offset read with two
  // clock reads inside the call, so a preempted call can move them by at most
  // its own duration: a slack measured, not assumed.
  const uint64_t slack = 1'000'000 + drained.longest_drain_ns;  // realtime→monotonic shift: a millisecond
  for (size_t i = 0; i < n; ++i) {
    EXPECT_EQ(out[i].id, 0x123u);
    EXPECT_EQ(out[i].data[0], i);
    EXPECT_GE(out[i].timestamp_ns + slack, before);
    EXPECT_LE(out[i].timestamp_ns, after + slack);
  }
  EXPECT_EQ(source.counters().frames, 5u);
}

TEST(SocketCanSource, KernelFiltersDropOtherIdentifiers) {
  if (!vcan_present()) GTEST_SKIP() << kNoVcan;
  SocketCanOptions options;
  options.interface = kVcan;
  SocketCanSource source(options);
  const FrameId ids[] = {{0x100, false}, {0x100, true}};
  ASSERT_TRUE(source.set_filters(ids, nullptr));
  ASSERT_TRUE(source.open(monotonic_ns(), nullptr));
  Sender sender(false);
  const uint8_t d[1] = {1};
  sender.send(make_data_frame(0x100, false, d, 1));
  sender.send(make_data_frame(0x101, false, d, 1));
  sender.send(make_data_frame(0x100, true, d, 1));
  std::array<CanFrame, 8> out;
  ASSERT_EQ(drain_expecting(source, out, 2).frames, 2u);
  EXPECT_FALSE(out[0].extended);
  EXPECT_TRUE(out[1].extended);
}

TEST(SocketCanSource, CanFdFramesWhenEnabled) {
  if (!vcan_present()) GTEST_SKIP() << kNoVcan;
  SocketCanOptions options;
  options.interface = kVcan;
  options.fd = true;
  SocketCanSource source(options);
  std::string error;
  ASSERT_TRUE(source.open(monotonic_ns(), &error)) << error;
  Sender sender(true);
  const JointStreamConfig config = default_joint_stream_config(8, true, 10'000'000);
  JointStreamSender encoder;
  ASSERT_TRUE(encoder.configure(config, nullptr));
  const int32_t values[8] = {1, 2, 3, 4, 5, 6, 7, 8};
  ASSERT_TRUE(sender.send(encoder.next(0, values)));
  std::array<CanFrame, 4> out;
  ASSERT_EQ(drain_expecting(source, out, 1).frames, 1u);
  EXPECT_TRUE(out[0].fd);
  EXPECT_EQ(out[0].len, 64);
}

TEST(SocketCanSource, DrainDoesNotAllocate) {
  if (!vcan_present()) GTEST_SKIP() << kNoVcan;
  SocketCanOptions options;
  options.interface = kVcan;
  SocketCanSource source(options);
  ASSERT_TRUE(source.open(monotonic_ns(), nullptr));
  Sender sender(false);
  std::array<CanFrame, 64> out;
  const uint8_t d[8] = {};
  test::AllocationCounter counter;
  for (int round = 0; round < 50; ++round) {
    sender.send(make_data_frame(0x100, false, d, 8));
    source.drain(out, monotonic_ns());
  }
  EXPECT_EQ(counter.allocations(), 0u);
}

}  // namespace
}  // namespace sinew::hal::can
