// The per-tick path end to end on the simulated bus: drain, decode, latch by
// timestamp, receive timeouts, bus-off and recovery, no allocation.
#include "hal/can/can_receiver.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <vector>

#include "hal/can/can_input_source.hpp"
#include "hal/can/candump_replay_source.hpp"
#include "hal/can/joint_stream_decoder.hpp"
#include "hal/can/joint_stream_encoder.hpp"
#include "hal/can/simulated_can_bus.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/time_units.hpp"

namespace sinew::hal::can {
namespace {

using sinew::test::kMs;
constexpr uint64_t kPeriod = 10 * kMs;  // default timeout 15 ms

class ReceiverTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const JointStreamConfig config = default_joint_stream_config(3, false, kPeriod);
    std::string error;
    ASSERT_TRUE(decoder_.configure(config, &error)) << error;
    ASSERT_TRUE(sender_.configure(config, &error)) << error;
    ASSERT_TRUE(receiver_.configure(bus_, decoder_, 32, 0, &error)) << error;
  }
  void send(size_t joint, int32_t value, uint64_t t_ns) { bus_.inject(sender_.next(joint, {&value, 1}, {}, t_ns)); }
  void send_all(int32_t value, uint64_t t_ns) {
    for (size_t j = 0; j < 3; ++j) send(j, value, t_ns);
  }
  std::vector<uint16_t> stale(uint64_t now) {
    const auto s = receiver_.stale_inputs(now);
    return {s.begin(), s.end()};
  }

  SimulatedCanBus bus_{256};
  JointStreamDecoder decoder_;
  JointStreamSender sender_;
  CanReceiver receiver_;
};

TEST_F(ReceiverTest, DecodesWhatArrivedUpToTheTickAndHoldsTheRest) {
  send(0, 11, 1 * kMs);
  send(1, 22, 2 * kMs);
  send(2, 33, 6 * kMs);  // after this tick
  PollResult r = receiver_.poll(5 * kMs, 7 * kMs);
  ASSERT_EQ(r.samples.size(), 2u);
  EXPECT_EQ(r.samples[0].value, 11);
  EXPECT_EQ(r.samples[1].value, 22);
  EXPECT_EQ(receiver_.held_frames(), 1u);
  r = receiver_.poll(10 * kMs, 10 * kMs);
  ASSERT_EQ(r.samples.size(), 1u);
  EXPECT_EQ(r.samples[0].input, 2);
  EXPECT_EQ(r.samples[0].timestamp_ns, 6 * kMs);
  EXPECT_EQ(receiver_.held_frames(), 0u);
}

TEST_F(ReceiverTest, RejectionsAreReportedWithTheirInput) {
  CanFrame bad = sender_.next(1, std::span<const int32_t>(), {}, 1 * kMs);
  bad.data[0] ^= 0xFF;
  bus_.inject(bad);
  const PollResult r = receiver_.poll(2 * kMs);
  EXPECT_TRUE(r.samples.empty());
  ASSERT_EQ(r.rejections.size(), 1u);
  EXPECT_EQ(r.rejections[0].input, 1);
  EXPECT_EQ(r.rejections[0].reason, RejectReason::kBadCrc);
  EXPECT_EQ(receiver_.decoder().counters(1).rejected[static_cast<size_t>(RejectReason::kBadCrc)], 1u);
}

TEST_F(ReceiverTest, FiltersKeepUnknownIdentifiersOffTheQueue) {
  CanFrame stray;
  stray.id = 0x7FF;
  stray.len = 8;
  EXPECT_FALSE(bus_.inject(stray));  // the decoder's identifiers were installed as filters
  EXPECT_EQ(receiver_.poll(1 * kMs).rejections.size(), 0u);
}

TEST_F(ReceiverTest, StaleAfterOneAndAHalfPeriodsWithoutAValidSample) {
  send_all(1, 1 * kMs);
  receiver_.poll(1 * kMs);
  EXPECT_TRUE(stale(16 * kMs).empty());  // 15 ms after the sample: not yet
  EXPECT_EQ(stale(16 * kMs + 1), (std::vector<uint16_t>{0, 1, 2}));
  EXPECT_EQ(receiver_.timeouts().stale_events(), 3u);
  EXPECT_EQ(stale(30 * kMs).size(), 3u);
  EXPECT_EQ(receiver_.timeouts().stale_events(), 3u);  // still stale: no new event

  send(1, 2, 31 * kMs);  // a valid sample clears it
  receiver_.poll(31 * kMs);
  EXPECT_EQ(stale(31 * kMs), (std::vector<uint16_t>{0, 2}));
  EXPECT_FALSE(receiver_.timeouts().is_stale(1, 31 * kMs));
}

TEST_F(ReceiverTest, AJointThatNeverSendsGoesStaleOneTimeoutAfterStart) {
  EXPECT_TRUE(stale(15 * kMs).empty());
  EXPECT_EQ(stale(15 * kMs + 1).size(), 3u);
}

TEST_F(ReceiverTest, RejectedFramesDoNotKeepAJointFresh) {
  send_all(1, 1 * kMs);
  receiver_.poll(1 * kMs);
  for (uint64_t t = 11 * kMs; t < 40 * kMs; t += kPeriod) {
    CanFrame bad = sender_.next(0, std::span<const int32_t>(), {}, t);
    bad.data[2] ^= 0x01;
    bus_.inject(bad);
    receiver_.poll(t);
  }
  EXPECT_TRUE(receiver_.timeouts().is_stale(0, 40 * kMs));
  EXPECT_EQ(decoder_.counters(0).rejected[static_cast<size_t>(RejectReason::kBadCrc)], 3u);
}

TEST_F(ReceiverTest, BusOffMakesJointsStaleAndRecoveryBringsThemBack) {
  send_all(1, 1 * kMs);
  receiver_.poll(1 * kMs);
  bus_.bus_off(5 * kMs);
  for (uint64_t t = 11 * kMs; t <= 41 * kMs; t += kPeriod) {
    send_all(2, t);  // lost: the controller is off the bus
    receiver_.poll(t);
  }
  EXPECT_EQ(receiver_.bus_state(), BusState::kBusOff);
  EXPECT_EQ(receiver_.bus_counters().bus_off_events, 1u);
  EXPECT_EQ(stale(41 * kMs).size(), 3u);

  bus_.restart(45 * kMs);
  send_all(3, 51 * kMs);
  const PollResult r = receiver_.poll(51 * kMs);
  EXPECT_EQ(receiver_.bus_state(), BusState::kErrorActive);
  EXPECT_EQ(receiver_.bus_counters().restarts, 1u);
  // After 50 ms of silence the counter check restarted, so the sender's
  // advanced counters are accepted at once.
  EXPECT_EQ(r.samples.size(), 3u);
  EXPECT_TRUE(stale(51 * kMs).empty());
}

TEST_F(ReceiverTest, TimestampsFromTheFutureAreClampedToNow) {
  send(0, 5, 1000 * kMs);
  const PollResult r = receiver_.poll(10 * kMs, 10 * kMs);
  ASSERT_EQ(r.samples.size(), 1u);
  EXPECT_EQ(r.samples[0].timestamp_ns, 10 * kMs);
}

TEST_F(ReceiverTest, MoreFramesThanCapacityWaitInTheQueue) {
  for (int i = 0; i < 40; ++i) send(0, i, static_cast<uint64_t>(i) * kMs / 10);
  EXPECT_EQ(receiver_.poll(10 * kMs).samples.size(), 32u);
  EXPECT_EQ(receiver_.poll(10 * kMs).samples.size(), 8u);
  EXPECT_EQ(decoder_.counters(0).accepted, 40u);
}

TEST_F(ReceiverTest, PerTickPathDoesNotAllocate) {
  test::AllocationCounter counter;
  for (uint64_t tick = 1; tick <= 500; ++tick) {
    const uint64_t t = tick * kMs;
    if (tick % 10 == 0) send_all(static_cast<int32_t>(tick), t);
    if (tick == 200) bus_.bus_off(t);
    if (tick == 300) bus_.restart(t);
    if (tick % 37 == 0) {
      CanFrame bad = sender_.next(2, std::span<const int32_t>(), {}, t);
      bad.data[0] ^= 1;
      bus_.inject(bad);
    }
    receiver_.poll(t);
    receiver_.stale_inputs(t);
  }
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_GT(decoder_.counters(0).accepted, 30u);
}

// Another device's frames never reach the decoder, but they are counted:
// a bus or log of nothing but foreign frames once read "ok, frames 0".
TEST_F(ReceiverTest, ForeignFramesAreCountedNotDecoded) {
  CanFrame foreign;
  foreign.id = 0x1ABCDEF;
  foreign.extended = true;
  foreign.len = 8;
  for (uint64_t t = 1; t <= 5; ++t) {
    foreign.timestamp_ns = t * kMs;
    bus_.inject(foreign);
  }
  send(0, 11, 2 * kMs);
  const PollResult r = receiver_.poll(10 * kMs, 10 * kMs);
  EXPECT_EQ(r.samples.size(), 1u);
  EXPECT_EQ(receiver_.bus_counters().foreign_frames, 5u);
  EXPECT_EQ(receiver_.bus_counters().frames, 1u);
}

// What an input-triggered tick asks between ticks: complete once a frame of
// every identifier has arrived up to now, without consuming any of them.
TEST_F(ReceiverTest, ArrivalIsCompleteOnceEveryIdentifierArrivedAndConsumesNothing) {
  send(0, 11, 1 * kMs);
  send(1, 22, 2 * kMs);
  EXPECT_FALSE(receiver_.arrival(3 * kMs).complete);
  send(0, 12, 3 * kMs);
  EXPECT_FALSE(receiver_.arrival(3 * kMs).complete) << "a second frame of joint 0 completes nothing";
  send(2, 33, 4 * kMs);
  test::AllocationCounter counter;
  const ArrivalState a = receiver_.arrival(4 * kMs);
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_TRUE(a.complete);
  EXPECT_FALSE(a.sync) << "no sync frame is configured";
  const PollResult r = receiver_.poll(4 * kMs);
  ASSERT_EQ(r.samples.size(), 4u) << "arrival() left every frame for the tick";
  EXPECT_EQ(r.samples[3].value, 33);
  EXPECT_FALSE(receiver_.arrival(5 * kMs).complete) << "the tick consumed the set";
}

TEST_F(ReceiverTest, FramesHeldBackByATickCountTowardsTheNextSet) {
  send_all(1, 1 * kMs);
  send_all(2, 6 * kMs);
  EXPECT_TRUE(receiver_.arrival(7 * kMs).complete);
  EXPECT_EQ(receiver_.poll(5 * kMs, 7 * kMs).samples.size(), 3u);  // the tick ends at 5 ms
  EXPECT_TRUE(receiver_.arrival(7 * kMs).complete) << "the 6 ms set is held, and complete";
}

class SyncReceiverTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const JointStreamConfig config = default_joint_stream_config(3, false, kPeriod);
    std::string error;
    ASSERT_TRUE(decoder_.configure(config, &error)) << error;
    ASSERT_TRUE(sender_.configure(config, &error)) << error;
    ASSERT_TRUE(receiver_.configure(bus_, decoder_, 32, 0, &error, {true, {0x080, false}})) << error;
  }
  void send(size_t joint, int32_t value, uint64_t t_ns) { bus_.inject(sender_.next(joint, {&value, 1}, {}, t_ns)); }
  void sync(uint64_t t_ns) {
    CanFrame f = make_data_frame(0x080, false, nullptr, 0);
    f.timestamp_ns = t_ns;
    bus_.inject(f);
  }

  SimulatedCanBus bus_{256};
  JointStreamDecoder decoder_;
  JointStreamSender sender_;
  CanReceiver receiver_;
};

// The sync frame closes the cycle: it passes the filters, is reported by
// arrival() and counted by poll(), and never reaches the decoder.
TEST_F(SyncReceiverTest, TheSyncFrameIsWatchedNotDecoded) {
  send(0, 11, 1 * kMs);
  EXPECT_FALSE(receiver_.arrival(2 * kMs).sync);
  sync(2 * kMs);
  const ArrivalState a = receiver_.arrival(2 * kMs);
  EXPECT_TRUE(a.sync);
  EXPECT_FALSE(a.complete) << "joints 1 and 2 sent nothing";
  const PollResult r = receiver_.poll(2 * kMs);
  ASSERT_EQ(r.samples.size(), 1u);
  EXPECT_TRUE(r.rejections.empty()) << "the sync frame is no unknown identifier";
  EXPECT_EQ(receiver_.sync_frames(), 1u);
  EXPECT_EQ(decoder_.unassigned().rejected_total(), 0u);
  EXPECT_FALSE(receiver_.arrival(3 * kMs).sync) << "the tick consumed it";
}

TEST_F(SyncReceiverTest, ASyncIdentifierThatCarriesJointsIsRefused) {
  CanReceiver other;
  SimulatedCanBus bus{16};
  std::string error;
  EXPECT_FALSE(other.configure(bus, decoder_, 32, 0, &error, {true, decoder_.frame_ids()[1]}));
  EXPECT_NE(error.find("sync"), std::string::npos) << error;
}

TEST(CandumpReplayForeign, ALogOfOnlyForeignFramesSaysSo) {
  const std::string path = testing::TempDir() + "/only_foreign.candump";
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    for (int i = 0; i < 4; ++i) std::fprintf(f, "(0000000001.%06d) can0 01ABCDEF#0011223344556677\n", i * 1000);
    std::fclose(f);
  }
  auto replay = std::make_unique<CandumpReplaySource>();
  std::string error;
  ASSERT_TRUE(replay->load({path, "", false, 0}, 0, &error)) << error;
  auto decoder = std::make_unique<JointStreamDecoder>();
  ASSERT_TRUE(decoder->configure(default_joint_stream_config(3, false, 10 * kMs), &error)) << error;
  auto source = CanInputSource::create("log", std::move(replay), std::move(decoder), 32, 0, &error);
  ASSERT_NE(source, nullptr) << error;
  std::vector<JointSample> out(32);
  InputHealth health;
  health.init(std::vector<InputLimits>(3), std::vector<int32_t>(3, 0), 0);
  source->latch(100 * kMs, out, health);
  const std::string line = source->status_line();
  EXPECT_NE(line.find("frames 0"), std::string::npos) << line;
  EXPECT_NE(line.find("foreign 4"), std::string::npos) << line;
  EXPECT_NE(line.find("identifiers this decoder does not read"), std::string::npos) << line;
}

}  // namespace
}  // namespace sinew::hal::can
