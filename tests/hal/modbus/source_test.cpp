// The Modbus input source against a real libmodbus server on 127.0.0.1:
// decoding, range rejection, exception responses, a server that goes away and
// comes back, a server that never answers, and a tick that never waits.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

#include "hal/common/input_health.hpp"
#include "hal/modbus/modbus_source.hpp"
#include "hal/modbus/sim/modbus_server.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/time_units.hpp"

namespace mb = sinew::hal::modbus;
namespace hal = sinew::hal;
namespace hal = sinew::hal;
using sinew::hal::sim::now_ns;

namespace {

using sinew::test::kMs;
constexpr int32_t kNinetyDegrees = 1 << 30;  // binary angle

mb::ChannelConfig joint_channel(uint16_t input, uint16_t address, mb::RegisterWidth width = mb::RegisterWidth::k16) {
  mb::ChannelConfig c;
  c.name = "joint" + std::to_string(input);
  c.input = input;
  c.address = address;
  c.width = width;
  return c;
}

mb::PollerConfig tcp_config(uint16_t port, std::vector<mb::ChannelConfig> channels) {
  mb::PollerConfig config;
  config.name = "plc";
  config.link.tcp.host = "127.0.0.1";
  config.link.tcp.port = port;
  config.channels = std::move(channels);
  config.period_ns = 5 * kMs;
  // Where the timeout is not the subject: long enough that a reply delayed by
  // load is still a reply, not a timeout that would change the state.
  config.response_timeout_ns = 1000 * kMs;
  config.backoff_initial_ns = 20 * kMs;
  config.backoff_max_ns = 160 * kMs;
  return config;
}

std::unique_ptr<mb::ModbusSource> create(const mb::PollerConfig& config) {
  std::string error;
  auto source = mb::ModbusSource::create(config, &error);
  EXPECT_NE(source, nullptr) << error;
  return source;
}

// Plays the runtime's tick: latch, apply, end the tick; remembers what was delivered.
class Tick {
 public:
  Tick(mb::ModbusSource& source, size_t inputs, uint64_t timeout_ns) : source_(source), last_ts_(inputs, 0) {
    const std::vector<hal::InputLimits> limits(inputs, hal::InputLimits{INT32_MIN, INT32_MAX, timeout_ns});
    const std::vector<int32_t> initial(inputs, 0);
    health.init(limits, initial, now_ns());
  }

  size_t step() {
    const uint64_t now = now_ns();
    health.begin_tick();
    const size_t n = source_.latch(now, samples_, health);
    health.apply(std::span<const hal::JointSample>(samples_.data(), n));
    health.end_tick(now);
    for (size_t i = 0; i < n; ++i) {
      const hal::JointSample& s = samples_[i];
      // Only new readings: each strictly newer than the last one delivered.
      if (s.timestamp_ns <= last_ts_[s.input] || s.timestamp_ns > now) ++not_new;
      last_ts_[s.input] = s.timestamp_ns;
      ++delivered;
    }
    rejected_this_tick = false;
    for (uint8_t st : health.status()) rejected_this_tick |= (st & hal::kJointRejected) != 0;
    return n;
  }

  // Ticks every millisecond until `done` holds or `timeout` passes (a liveness
  // bound: success returns at once).
  template <typename Done>
  bool until(Done done, std::chrono::milliseconds timeout = std::chrono::milliseconds(30000)) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      step();
      if (done()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
  }

  int32_t value(size_t input) const { return health.values()[input]; }
  bool stale(size_t input) const { return (health.status()[input] & hal::kJointStale) != 0; }
  uint64_t rejected(size_t input, hal::RejectReason r) const {
    return health.counters(input).rejected[static_cast<int>(r)];
  }

  hal::InputHealth health;
  uint64_t delivered = 0;
  uint64_t not_new = 0;
  bool rejected_this_tick = false;

 private:
  mb::ModbusSource& source_;
  std::vector<hal::JointSample> samples_ = std::vector<hal::JointSample>(64);
  std::vector<uint64_t> last_ts_;
};

}  // namespace

TEST(ModbusSource, Decodes16And32BitValuesInBothWordOrders) {
  sinew::hal::sim::ModbusServer server;
  server.set_holding(10, 900);                                     // u16 x 0.1 = 90 deg
  server.set_holding(11, static_cast<uint16_t>(-200));             // s16 x 0.5 + 10 = -90 deg
  server.set_holding32(12, static_cast<uint32_t>(-450000), true);  // s32 ABCD x 1e-4 = -45 deg
  server.set_holding32(14, 100000, false);                         // u32 CDAB x 0.001 - 10 = 90 deg
  server.set_input32(0, static_cast<uint32_t>(-1500), false);      // s32 CDAB x 0.001 = -1.5 rig units
  server.set_input32(2, static_cast<uint32_t>(-1000), true);       // s32 ABCD x 0.01 = -10 N
  ASSERT_TRUE(server.start());

  std::vector<mb::ChannelConfig> channels{joint_channel(0, 10),
                                          joint_channel(1, 11),
                                          joint_channel(2, 12, mb::RegisterWidth::k32),
                                          joint_channel(3, 14, mb::RegisterWidth::k32),
                                          joint_channel(4, 0, mb::RegisterWidth::k32),
                                          joint_channel(5, 2, mb::RegisterWidth::k32)};
  channels[0].is_signed = false;
  channels[0].scale = 0.1;
  channels[1].scale = 0.5;
  channels[1].offset = 10.0;
  channels[2].scale = 1e-4;
  channels[3].is_signed = false;
  channels[3].word_order = mb::WordOrder::kLowWordFirst;
  channels[3].scale = 0.001;
  channels[3].offset = -10.0;
  channels[4].table = mb::RegisterTable::kInput;
  channels[4].word_order = mb::WordOrder::kLowWordFirst;
  channels[4].scale = 0.001;
  channels[4].quantity = mb::Quantity::kTranslation;
  channels[4].min = -10.0;
  channels[4].max = 10.0;
  channels[5].table = mb::RegisterTable::kInput;
  channels[5].scale = 0.01;
  channels[5].quantity = mb::Quantity::kForce;
  channels[5].min = -500.0;
  channels[5].max = 500.0;

  auto source = create(tcp_config(server.port(), channels));
  ASSERT_NE(source, nullptr);
  EXPECT_EQ(source->request_count(), 2u);  // holding 10..15 and input 0..3
  Tick tick(*source, 6, 0);
  ASSERT_TRUE(tick.until([&] { return tick.value(5) != 0 && source->state() == hal::SourceState::kOk; }));
  EXPECT_EQ(tick.value(0), kNinetyDegrees);
  EXPECT_EQ(tick.value(1), -kNinetyDegrees);
  EXPECT_EQ(tick.value(2), -kNinetyDegrees / 2);
  EXPECT_EQ(tick.value(3), kNinetyDegrees);
  EXPECT_EQ(tick.value(4), -1572864);  // -1.5 in Q12.20
  EXPECT_EQ(tick.value(5), -655360);   // -10 N in Q16.16

  // A few more cycles: readings keep coming, each delivered once.
  const uint64_t before = tick.delivered;
  ASSERT_TRUE(tick.until([&] { return tick.delivered >= before + 30; }));
  EXPECT_EQ(tick.not_new, 0u);
  EXPECT_EQ(source->counters().exceptions, 0u);
  // Nothing is latched before it was read.
  std::array<hal::JointSample, 8> out{};
  EXPECT_EQ(source->latch(0, out, tick.health), 0u);
  std::printf("status: %s\n", source->status_line().c_str());
}

TEST(ModbusSource, RejectsOutOfRangeValuesAndReportsThem) {
  sinew::hal::sim::ModbusServer server;
  server.set_holding(0, 1000);  // 100 deg: outside [-90, 90]
  ASSERT_TRUE(server.start());
  std::vector<mb::ChannelConfig> channels{joint_channel(0, 0)};
  channels[0].scale = 0.1;
  channels[0].min = -90.0;
  channels[0].max = 90.0;
  auto source = create(tcp_config(server.port(), channels));
  ASSERT_NE(source, nullptr);
  Tick tick(*source, 1, 0);

  bool flagged = false;
  // The channel's status is that of the latest cycle, so it is awaited with the
  // counts rather than sampled once.
  ASSERT_TRUE(tick.until([&] {
    flagged |= tick.rejected_this_tick;
    return tick.rejected(0, hal::RejectReason::kOutOfRange) >= 3 &&
           source->channel(0).status == mb::ChannelStatus::kOutOfRange;
  }));
  EXPECT_TRUE(flagged);
  EXPECT_EQ(tick.value(0), 0);  // held at its initial value
  EXPECT_EQ(tick.delivered, 0u);
  EXPECT_GE(source->counters().out_of_range, 3u);
  // Every rejection reaches the health counters exactly once.
  tick.step();
  EXPECT_EQ(tick.rejected(0, hal::RejectReason::kOutOfRange), source->channel(0).out_of_range);

  server.set_holding(0, 450);  // 45 deg
  ASSERT_TRUE(tick.until(
      [&] { return tick.value(0) == kNinetyDegrees / 2 && source->channel(0).status == mb::ChannelStatus::kOk; }));
}

TEST(ModbusSource, CountsExceptionResponsesAndHoldsTheJoint) {
  sinew::hal::sim::ModbusServer server;
  server.set_holding(10, 300);  // 30 deg
  ASSERT_TRUE(server.start());
  // Input 1 reads an address the server does not map: "illegal data address".
  const uint16_t unmapped = sinew::hal::sim::ModbusServer::kRegisters + 44;
  std::vector<mb::ChannelConfig> channels{joint_channel(0, 10), joint_channel(1, unmapped)};
  channels[0].scale = 0.1;
  auto source = create(tcp_config(server.port(), channels));
  ASSERT_NE(source, nullptr);
  // 500 ms: a fresh input stays fresh across a poller delayed by load.
  Tick tick(*source, 2, 500 * kMs);
  const int32_t thirty = mb::to_engine(mb::Quantity::kAngle, 30.0);

  // The state and the channel statuses are those of the latest cycle and the
  // freshness that of the latest sample, so they are awaited together with the
  // cumulative counts rather than sampled once afterwards.
  bool flagged = false;  // kJointRejected on input 1 in some tick
  ASSERT_TRUE(tick.until([&] {
    flagged |= (tick.health.status()[1] & hal::kJointRejected) != 0;
    return tick.value(0) == thirty && source->counters().by_exception[2] >= 3 && tick.stale(1) && !tick.stale(0) &&
           source->state() == hal::SourceState::kDegraded && source->channel(1).status == mb::ChannelStatus::kException;
  }));
  EXPECT_TRUE(flagged);
  EXPECT_EQ(source->channel(1).last_exception, 2);  // illegal data address
  EXPECT_GE(tick.rejected(1, hal::RejectReason::kMalformed), 3u);
  EXPECT_EQ(tick.value(1), 0);

  // The device now fails the block input 0 is read from: input 0 holds 30 deg
  // and goes stale; the failures are counted under their own code. The block
  // fails before its value changes, so no cycle can read 60 deg in between.
  server.fail_reads_at(10, 4);  // server device failure
  server.set_holding(10, 600);
  ASSERT_TRUE(tick.until([&] {
    return source->counters().by_exception[4] >= 3 && tick.stale(0) && source->channel(0).last_exception == 4 &&
           source->state() == hal::SourceState::kDegraded;  // answered, but with exceptions only
  }));
  EXPECT_EQ(tick.value(0), thirty);
  const std::string line = source->status_line();
  EXPECT_NE(line.find("server device failure"), std::string::npos) << line;
  EXPECT_NE(line.find("illegal data address"), std::string::npos) << line;
  std::printf("status: %s\n", line.c_str());

  server.fail_reads_at(-1, 0);
  const int32_t sixty = mb::to_engine(mb::Quantity::kAngle, 60.0);
  ASSERT_TRUE(tick.until([&] { return tick.value(0) == sixty && !tick.stale(0); }));
}

TEST(ModbusSource, GoesDownBacksOffAndRecoversWhenTheServerReturns) {
  sinew::hal::sim::ModbusServer server;
  server.set_holding(0, 100);
  ASSERT_TRUE(server.start());
  const uint16_t port = server.port();
  auto source = create(tcp_config(port, {joint_channel(0, 0)}));
  ASSERT_NE(source, nullptr);
  // 500 ms: the input recovered below stays fresh across a poller delayed by load.
  Tick tick(*source, 1, 500 * kMs);
  ASSERT_TRUE(tick.until([&] { return tick.value(0) != 0 && source->state() == hal::SourceState::kOk; }));

  server.stop();
  // The waits double from 20 ms to the 160 ms cap (the poller shows each wait
  // before it sleeps it).
  constexpr uint64_t kCap = 160 * kMs;
  ASSERT_TRUE(tick.until([&] {
    return source->state() == hal::SourceState::kDown && tick.stale(0) && source->counters().backoff_ns == kCap;
  }));
  // At the cap every failed attempt is followed by a full 160 ms wait, so
  // within any interval of E ns at most 1 + E / 160 ms attempts can be counted,
  // however the threads are scheduled: a bound by order of events, not speed.
  // Watched for 1 s at least, and until two attempts show it is still retrying.
  const auto start = std::chrono::steady_clock::now();
  const uint64_t failures_before = source->counters().connect_failures;
  uint64_t attempts = 0;
  ASSERT_TRUE(tick.until([&] {
    attempts = source->counters().connect_failures - failures_before;
    return attempts >= 2 && std::chrono::steady_clock::now() - start >= std::chrono::seconds(1);
  }));
  const auto elapsed_ns = static_cast<uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count());
  EXPECT_LE(attempts, 1 + elapsed_ns / kCap) << "not hundreds a second";
  EXPECT_EQ(source->counters().backoff_ns, kCap);
  EXPECT_GE(source->counters().link_errors, 1u);
  std::printf("attempts in %.2f s while down: %llu; status: %s\n", static_cast<double>(elapsed_ns) / 1e9,
              static_cast<unsigned long long>(attempts), source->status_line().c_str());

  server.set_holding(0, 20);
  ASSERT_TRUE(server.start(port));
  const int32_t twenty = mb::to_engine(mb::Quantity::kAngle, 20.0);
  // The poller shows kOk just before it resets the wait: both are awaited.
  ASSERT_TRUE(tick.until([&] {
    return source->state() == hal::SourceState::kOk && tick.value(0) == twenty && !tick.stale(0) &&
           source->counters().backoff_ns == 0;
  }));
  EXPECT_GE(source->counters().connects, 2u);
}

// "The tick never waits", shown by the order of events rather than by
// durations: the server has read the poller's only request and never answers,
// so the poller sits in that one read until its response timeout, far beyond
// the test. While it sits there (no cycle completed, no timeout counted) the
// tick runs on, and flags the input stale on its own clock.
TEST(ModbusSource, TheTickNeverWaitsForAServerThatDoesNotAnswer) {
  sinew::hal::sim::ModbusServer server;
  server.set_mute(true);
  ASSERT_TRUE(server.start());
  auto config = tcp_config(server.port(), {joint_channel(0, 0)});
  config.response_timeout_ns = 30'000 * kMs;
  auto source = create(config);
  ASSERT_NE(source, nullptr);
  Tick tick(*source, 1, 50 * kMs);

  // The server holds the request: from here on the poller is blocked in its read.
  ASSERT_TRUE(tick.until([&] { return server.requests() >= 1; }));
  // 20 ticks at least, and on until the input is stale (50 ms after the start).
  std::vector<uint64_t> durations;
  durations.reserve(100000);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);  // a liveness bound
  while ((durations.size() < 20 || !tick.stale(0)) && std::chrono::steady_clock::now() < deadline &&
         durations.size() < durations.capacity()) {
    const uint64_t t0 = now_ns();
    tick.step();
    durations.push_back(now_ns() - t0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_TRUE(tick.stale(0));
  // Still inside that read: every tick above ran while the poller waited.
  const mb::PollerCounters counters = source->counters();
  EXPECT_EQ(counters.requests, 1u);
  EXPECT_EQ(counters.cycles, 0u);
  EXPECT_EQ(counters.timeouts, 0u);
  EXPECT_EQ(tick.delivered, 0u);
  std::sort(durations.begin(), durations.end());
  std::printf("%zu ticks while the poller waited; latch+apply median %.2f us, worst %.1f us (printed, not judged)\n",
              durations.size(), static_cast<double>(durations[durations.size() / 2]) / 1e3,
              static_cast<double>(durations.back()) / 1e3);
  server.stop();  // the poller's read ends at once, so the source stops without waiting out the timeout
}

// The poller gives up on a silent server after its response timeout, neither
// early nor never. The server measures each wait from reading the request to
// seeing the hang-up; a late server thread can shorten that by its own delay,
// hence the wide margins: half the timeout below, ten times above.
TEST(ModbusSource, SilentServerHonoursTheResponseTimeout) {
  sinew::hal::sim::ModbusServer server;
  server.set_mute(true);
  ASSERT_TRUE(server.start());
  auto config = tcp_config(server.port(), {joint_channel(0, 0)});
  constexpr uint64_t kTimeout = 2000 * kMs;
  config.response_timeout_ns = kTimeout;
  config.backoff_initial_ns = 10 * kMs;
  config.backoff_max_ns = 10 * kMs;
  auto source = create(config);
  ASSERT_NE(source, nullptr);
  Tick tick(*source, 1, 50 * kMs);

  ASSERT_TRUE(tick.until([&] { return server.silences_ns().size() >= 2; }));
  tick.step();  // the snapshots of those cycles were published before the hang-ups
  for (uint64_t silence : server.silences_ns()) {
    std::printf("client waited %.1f ms for an answer\n", static_cast<double>(silence) / 1e6);
    EXPECT_GE(silence, kTimeout / 2);
    EXPECT_LE(silence, 10 * kTimeout);
  }
  EXPECT_EQ(source->state(), hal::SourceState::kDown);
  EXPECT_GE(source->counters().timeouts, 2u);
  EXPECT_EQ(source->channel(0).status, mb::ChannelStatus::kNoResponse);
  EXPECT_TRUE(tick.stale(0));
}

TEST(ModbusSource, LatchDoesNotAllocate) {
  sinew::hal::sim::ModbusServer server;
  for (uint16_t a = 0; a < 8; ++a) server.set_holding(a, static_cast<uint16_t>(10 * a));
  server.set_holding(8, 5000);  // out of range below
  ASSERT_TRUE(server.start());
  std::vector<mb::ChannelConfig> channels;
  for (uint16_t i = 0; i < 9; ++i) channels.push_back(joint_channel(i, i));
  channels.push_back(joint_channel(9, sinew::hal::sim::ModbusServer::kRegisters + 1));  // exception every cycle
  auto source = create(tcp_config(server.port(), channels));
  ASSERT_NE(source, nullptr);
  Tick tick(*source, 10, 0);
  ASSERT_TRUE(tick.until([&] {
    return tick.delivered >= 40 && tick.rejected(8, hal::RejectReason::kOutOfRange) > 0 &&
           tick.rejected(9, hal::RejectReason::kMalformed) > 0;
  }));

  const uint64_t delivered_before = tick.delivered;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  sinew::test::AllocationCounter counter;
  // 300 ticks, and on until one of them latched a new sample (the deadline is
  // a liveness bound: a new sample normally comes within milliseconds).
  for (int i = 0; i < 300 || (tick.delivered == delivered_before && std::chrono::steady_clock::now() < deadline); ++i) {
    tick.step();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const uint64_t allocations = counter.allocations();
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(tick.delivered, delivered_before);  // the loop did latch new samples
}

TEST(ModbusSource, MissingSerialDeviceIsDownAndRetried) {
  mb::PollerConfig config;
  config.name = "rs485";
  config.link.transport = mb::Transport::kRtu;
  config.link.rtu.device = "no-such-serial-device";
  config.channels = {joint_channel(0, 0)};
  config.backoff_initial_ns = 10 * kMs;
  config.backoff_max_ns = 40 * kMs;
  auto source = create(config);
  ASSERT_NE(source, nullptr);
  Tick tick(*source, 1, 0);
  ASSERT_TRUE(tick.until([&] { return source->counters().connect_failures >= 3; }));
  EXPECT_EQ(source->state(), hal::SourceState::kDown);
  EXPECT_EQ(source->channel(0).status, mb::ChannelStatus::kNoResponse);
}

TEST(ModbusSource, RefusesInvalidConfig) {
  std::string error;
  mb::PollerConfig config = tcp_config(502, {joint_channel(0, 0), joint_channel(0, 1)});
  EXPECT_EQ(mb::ModbusSource::create(config, &error), nullptr);
  EXPECT_NE(error.find("plc"), std::string::npos) << error;
}
