// The UDP stream end to end on 127.0.0.1 (ephemeral ports, bounded waits):
// exact round trips of small and multi-datagram frames, a skipped fragment
// counted as a loss, reordering through a relay, and a non-blocking,
// allocation-free sender.
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>

#include "datagrams.hpp"
#include "hal/output/udp_sender.hpp"
#include "host_tools/receiver/udp_receiver.hpp"
#include "test_poses.hpp"
#include "tests/support/alloc_guard.hpp"

namespace sinew::test {
namespace {

using hal::output::DecodedPose;
using hal::output::UdpSender;
using receiver::ReceiveResult;
using receiver::UdpReceiver;

// A liveness bound for datagrams already sent: success returns as soon as they
// arrive (microseconds on loopback), so only a lost datagram waits it out.
constexpr int kWaitMs = 30000;
constexpr uint32_t kLargeMesh = 4192;

void open_receiver(UdpReceiver& r) {
  receiver::UdpReceiverOptions options;
  options.bind_address = "127.0.0.1";
  std::string error;
  ASSERT_TRUE(r.open(options, &error)) << error;
  ASSERT_NE(r.port(), 0);
}

void open_sender(UdpSender& s, uint16_t port, const TestPose& pose, hal::output::UdpSenderOptions options = {}) {
  std::string error;
  ASSERT_TRUE(s.open("127.0.0.1", port, pose.shape(), options, &error)) << error;
}

// A plain socket the sender sends to: captures datagrams and forwards them in any order.
class Relay {
 public:
  Relay() {
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof(a);
    EXPECT_EQ(::bind(fd_, reinterpret_cast<sockaddr*>(&a), len), 0);
    EXPECT_EQ(::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len), 0);
    port_ = ntohs(a.sin_port);
    const int big = 4 << 20;
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &big, sizeof(big));
  }
  ~Relay() { ::close(fd_); }
  uint16_t port() const { return port_; }

  std::vector<Datagram> capture(size_t n) {
    std::vector<Datagram> out;
    Datagram buf(65536);
    while (out.size() < n) {
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, kWaitMs) != 1) break;
      const ssize_t got = ::recv(fd_, buf.data(), buf.size(), 0);
      if (got < 0) break;
      out.emplace_back(buf.begin(), buf.begin() + got);
    }
    return out;
  }

  void forward(const Datagram& d, uint16_t port) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(port);
    EXPECT_EQ(::sendto(fd_, d.data(), d.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof(a)),
              static_cast<ssize_t>(d.size()));
  }

 private:
  int fd_ = -1;
  uint16_t port_ = 0;
};

TEST(UdpLoopback, SmallFrameIsOneDatagram) {
  UdpReceiver rx;
  open_receiver(rx);
  TestPose pose(10, 3, true);
  UdpSender tx;
  open_sender(tx, rx.port(), pose);
  DecodedPose got;
  std::string error;
  for (uint64_t t = 0; t < 3; ++t) {
    pose.set_tick(t);
    ASSERT_TRUE(tx.write(pose.frame()));
    ASSERT_EQ(rx.receive(kWaitMs, &got, &error), ReceiveResult::kFrame) << error;
    expect_same_pose(got, pose.frame(), true);
    EXPECT_EQ(rx.sequence(), t);
  }
  EXPECT_EQ(tx.stats().datagrams_sent, 3u);
  EXPECT_EQ(rx.stats().frames_lost, 0u);
}

TEST(UdpLoopback, LargeMeshRoundTripsExactly) {
  for (const bool normals : {false, true}) {
    SCOPED_TRACE(normals ? "with normals" : "positions only");
    UdpReceiver rx;
    open_receiver(rx);
    TestPose pose(kLargeMesh, 24, normals);
    UdpSender tx;
    open_sender(tx, rx.port(), pose);
    const size_t payload = 32 + (normals ? 24u : 12u) * kLargeMesh + 5u * 24;
    const size_t fragments = (payload + tx.fragment_payload_bytes() - 1) / tx.fragment_payload_bytes();
    EXPECT_GT(fragments, 30u);
    DecodedPose got;
    std::string error;
    for (uint64_t t = 0; t < 5; ++t) {
      pose.set_tick(t);
      ASSERT_TRUE(tx.write(pose.frame()));
      ASSERT_EQ(rx.receive(kWaitMs, &got, &error), ReceiveResult::kFrame) << error;
      expect_same_pose(got, pose.frame(), normals);
    }
    EXPECT_EQ(tx.stats().datagrams_sent, 5 * fragments);
    EXPECT_EQ(rx.stats().frames_delivered, 5u);
    EXPECT_EQ(rx.stats().frames_lost, 0u);
    EXPECT_EQ(rx.stats().bad_datagrams, 0u);
  }
}

TEST(UdpLoopback, DatagramsFitTheDefaultSize) {
  Relay relay;
  TestPose pose(kLargeMesh, 8, false);
  UdpSender tx;
  open_sender(tx, relay.port(), pose);
  ASSERT_TRUE(tx.write(pose.frame()));
  const auto datagrams = relay.capture(tx.stats().datagrams_sent);
  ASSERT_EQ(datagrams.size(), tx.stats().datagrams_sent);
  for (const Datagram& d : datagrams) EXPECT_LE(d.size(), 1400u);
  EXPECT_EQ(datagrams.front().size(), 1400u);
}

TEST(UdpLoopback, SkippedFragmentIsACountedLossNotAWrongFrame) {
  UdpReceiver rx;
  open_receiver(rx);
  TestPose pose(kLargeMesh, 4, false);
  UdpSender tx;
  open_sender(tx, rx.port(), pose);
  DecodedPose got;
  std::string error;

  tx.skip_fragment_for_test(7);
  pose.set_tick(0);
  ASSERT_TRUE(tx.write(pose.frame()));
  EXPECT_EQ(rx.receive(300, &got, &error), ReceiveResult::kTimeout);  // frame 0 never completes

  tx.skip_fragment_for_test(-1);
  pose.set_tick(1);
  ASSERT_TRUE(tx.write(pose.frame()));
  ASSERT_EQ(rx.receive(kWaitMs, &got, &error), ReceiveResult::kFrame) << error;
  expect_same_pose(got, pose.frame(), false);
  EXPECT_EQ(rx.sequence(), 1u);
  // The first delivered frame starts the count; a loss shows from the next one.
  tx.skip_fragment_for_test(0);
  pose.set_tick(2);
  tx.write(pose.frame());
  tx.skip_fragment_for_test(-1);
  pose.set_tick(3);
  tx.write(pose.frame());
  ASSERT_EQ(rx.receive(kWaitMs, &got, &error), ReceiveResult::kFrame) << error;
  expect_same_pose(got, pose.frame(), false);
  EXPECT_EQ(rx.stats().frames_delivered, 2u);
  EXPECT_EQ(rx.stats().frames_lost, 1u);
  EXPECT_EQ(rx.stats().frames_incomplete, 2u);
}

TEST(UdpLoopback, ReorderedDatagramsThroughARelay) {
  UdpReceiver rx;
  open_receiver(rx);
  Relay relay;
  std::vector<std::unique_ptr<TestPose>> poses;
  UdpSender tx;
  poses.push_back(std::make_unique<TestPose>(600, 6, false));
  open_sender(tx, relay.port(), *poses[0]);
  for (uint64_t t = 0; t < 5; ++t) {
    if (t > 0) poses.push_back(std::make_unique<TestPose>(600, 6, false));
    poses[t]->set_tick(t);
    ASSERT_TRUE(tx.write(poses[t]->frame()));
  }
  const size_t per_frame = tx.stats().datagrams_sent / 5;
  ASSERT_GE(per_frame, 3u);
  const auto captured = relay.capture(tx.stats().datagrams_sent);
  ASSERT_EQ(captured.size(), 5 * per_frame);
  auto frame = [&](size_t f) {
    return std::vector<Datagram>(captured.begin() + static_cast<std::ptrdiff_t>(f * per_frame),
                                 captured.begin() + static_cast<std::ptrdiff_t>((f + 1) * per_frame));
  };
  std::vector<Datagram> order;
  auto f0 = frame(0);  // frame 0: fragments reversed
  order.insert(order.end(), f0.rbegin(), f0.rend());
  auto f1 = frame(1), f2 = frame(2);  // frames 1 and 2 interleaved, frame 2's last fragment at the end
  for (size_t i = 0; i + 1 < per_frame; ++i) {
    order.push_back(f2[i]);
    order.push_back(f1[i]);
  }
  order.push_back(f1.back());
  order.push_back(f2.back());
  auto f3 = frame(3), f4 = frame(4);  // frame 4 entirely before frame 3: 3 is stale
  order.insert(order.end(), f4.begin(), f4.end());
  order.insert(order.end(), f3.begin(), f3.end());
  for (const Datagram& d : order) relay.forward(d, rx.port());

  // Received until every forwarded datagram has been taken in (not until a
  // quiet spell, which a late datagram on a loaded machine would end early),
  // then nothing more may come.
  std::vector<uint64_t> ticks;
  DecodedPose got;
  std::string error;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(kWaitMs);
  while (rx.stats().datagrams < order.size() && std::chrono::steady_clock::now() < deadline) {
    const ReceiveResult result = rx.receive(100, &got, &error);
    ASSERT_NE(result, ReceiveResult::kError) << error;
    if (result != ReceiveResult::kFrame) continue;
    ticks.push_back(got.tick);
    expect_same_pose(got, poses[got.tick]->frame(), false);
  }
  ASSERT_EQ(rx.stats().datagrams, order.size());
  EXPECT_EQ(rx.receive(50, &got, &error), ReceiveResult::kTimeout);
  EXPECT_EQ(ticks, (std::vector<uint64_t>{0, 1, 2, 4}));
  EXPECT_EQ(rx.stats().frames_lost, 1u);
  EXPECT_EQ(rx.stats().frames_out_of_order, 1u);
  EXPECT_EQ(rx.stats().bad_datagrams, 0u);
}

TEST(UdpLoopback, SenderNeverBlocksOnAnUnreadSocket) {
  UdpReceiver rx;  // bound, never read: the kernel drops what does not fit
  open_receiver(rx);
  TestPose pose(kLargeMesh, 4, false);
  UdpSender tx;
  hal::output::UdpSenderOptions options;
  options.send_buffer_bytes = 4096;
  open_sender(tx, rx.port(), pose, options);
  const auto start = std::chrono::steady_clock::now();
  constexpr uint64_t kFrames = 300;
  for (uint64_t t = 0; t < kFrames; ++t) {
    pose.set_tick(t);
    tx.write(pose.frame());
  }
  // Only a liveness bound (a sender blocking on the unread socket would never
  // return); the time is not a speed claim.
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 60.0);
  EXPECT_EQ(tx.stats().frames_sent + tx.stats().frames_dropped, kFrames);
  EXPECT_EQ(tx.next_sequence(), kFrames);
}

TEST(UdpLoopback, WritePathDoesNotAllocate) {
  UdpReceiver rx;
  open_receiver(rx);
  TestPose pose(kLargeMesh, 16, true);
  UdpSender tx;
  open_sender(tx, rx.port(), pose);
  AllocationCounter counter;
  for (uint64_t t = 0; t < 50; ++t) {
    pose.set_tick(t);
    tx.write(pose.frame());
  }
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_EQ(tx.stats().frames_sent + tx.stats().frames_dropped, 50u);
}

TEST(UdpLoopback, OpenChecksItsOptions) {
  TestPose pose(10, 1, false);
  UdpSender tx;
  std::string error;
  hal::output::UdpSenderOptions options;
  options.max_datagram_bytes = 40;
  EXPECT_FALSE(tx.open("127.0.0.1", 9, pose.shape(), options, &error));
  options.max_datagram_bytes = 65508;
  EXPECT_FALSE(tx.open("127.0.0.1", 9, pose.shape(), options, &error));
  options.max_datagram_bytes = 1400;
  options.stream_id = 1234;
  ASSERT_TRUE(tx.open("127.0.0.1", 9, pose.shape(), options, &error)) << error;
  EXPECT_EQ(tx.stream_id(), 1234u);
  options.stream_id = 0;
  ASSERT_TRUE(tx.open("127.0.0.1", 9, pose.shape(), options, &error)) << error;
  EXPECT_NE(tx.stream_id(), 0u);
}

TEST(UdpLoopback, FrameOfAnotherShapeIsRejected) {
  TestPose pose(10, 1, false), other(11, 1, false);
  UdpSender tx;
  open_sender(tx, 9, pose);
  EXPECT_FALSE(tx.write(other.frame()));
  EXPECT_EQ(tx.stats().frames_rejected, 1u);
  EXPECT_EQ(tx.next_sequence(), 1u);  // a gap at the receiver
}

}  // namespace
}  // namespace sinew::test
