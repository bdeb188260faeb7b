// The pure parts of the Modbus backend: register decoding, conversion to
// engine units, range checks, request grouping, back-off, the triple-buffer
// hand-off and the status register image.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <thread>
#include <vector>

#include "hal/common/pose_frame.hpp"
#include "hal/common/triple_buffer.hpp"
#include "hal/modbus/backoff.hpp"
#include "hal/modbus/poller_config.hpp"
#include "hal/modbus/request_plan.hpp"
#include "hal/modbus/status_registers.hpp"

namespace mb = sinew::hal::modbus;
namespace hal = sinew::hal;

namespace {

constexpr int32_t kQuarterTurn = 1 << 30;

mb::ChannelConfig channel(uint16_t address, mb::RegisterWidth width = mb::RegisterWidth::k16,
                          mb::RegisterTable table = mb::RegisterTable::kHolding) {
  mb::ChannelConfig c;
  c.address = address;
  c.width = width;
  c.table = table;
  return c;
}

std::array<uint16_t, 2> words(uint32_t v, bool high_first) {
  const auto hi = static_cast<uint16_t>(v >> 16), lo = static_cast<uint16_t>(v & 0xFFFF);
  return high_first ? std::array<uint16_t, 2>{hi, lo} : std::array<uint16_t, 2>{lo, hi};
}

}  // namespace

TEST(ModbusCodec, Decodes16BitSignedAndUnsigned) {
  mb::ChannelConfig c = channel(0);
  const std::array<uint16_t, 1> reg{0xFF38};
  c.is_signed = true;
  EXPECT_EQ(mb::decode_raw(c, reg), -200);
  c.is_signed = false;
  EXPECT_EQ(mb::decode_raw(c, reg), 0xFF38);
}

TEST(ModbusCodec, Decodes32BitInBothWordOrders) {
  mb::ChannelConfig c = channel(0, mb::RegisterWidth::k32);
  for (const bool high_first : {true, false}) {
    c.word_order = high_first ? mb::WordOrder::kHighWordFirst : mb::WordOrder::kLowWordFirst;
    c.is_signed = true;
    EXPECT_EQ(mb::decode_raw(c, words(static_cast<uint32_t>(-450000), high_first)), -450000);
    EXPECT_EQ(mb::decode_raw(c, words(0x12345678u, high_first)), 0x12345678);
    c.is_signed = false;
    EXPECT_EQ(mb::decode_raw(c, words(0xFFFFFFFEu, high_first)), int64_t{0xFFFFFFFE});
  }
}

TEST(ModbusCodec, ScalesAndConvertsToEngineUnits) {
  EXPECT_EQ(mb::to_engine(mb::Quantity::kAngle, 90.0), kQuarterTurn);
  EXPECT_EQ(mb::to_engine(mb::Quantity::kAngle, -90.0), -kQuarterTurn);
  EXPECT_EQ(mb::to_engine(mb::Quantity::kAngle, 180.0), INT32_MAX);  // saturates, one LSB short
  EXPECT_EQ(mb::to_engine(mb::Quantity::kAngle, -180.0), INT32_MIN);
  EXPECT_EQ(mb::to_engine(mb::Quantity::kTranslation, 1.5), 1572864);  // Q12.20
  EXPECT_EQ(mb::to_engine(mb::Quantity::kForce, -10.0), -655360);      // Q16.16
  // Round half up, as in the engine: +0.5 LSB -> 1, -0.5 LSB -> 0.
  EXPECT_EQ(mb::to_engine(mb::Quantity::kTranslation, 0.5 / 1048576.0), 1);
  EXPECT_EQ(mb::to_engine(mb::Quantity::kTranslation, -0.5 / 1048576.0), 0);

  mb::ChannelConfig c = channel(0, mb::RegisterWidth::k32);
  c.word_order = mb::WordOrder::kLowWordFirst;
  c.is_signed = false;
  c.scale = 0.001;
  c.offset = -10.0;
  const mb::Conversion v = mb::convert(c, words(100000, false));
  ASSERT_TRUE(v.accepted);
  EXPECT_DOUBLE_EQ(v.physical, 90.0);
  EXPECT_EQ(v.value, kQuarterTurn);
}

TEST(ModbusCodec, RejectsValuesOutsideTheConfiguredRange) {
  mb::ChannelConfig c = channel(0);
  c.scale = 0.1;
  c.min = -90.0;
  c.max = 90.0;
  const std::array<uint16_t, 1> at_max{900}, beyond{901}, below{static_cast<uint16_t>(-901)};
  EXPECT_TRUE(mb::convert(c, at_max).accepted);
  EXPECT_FALSE(mb::convert(c, beyond).accepted);
  EXPECT_FALSE(mb::convert(c, below).accepted);
}

TEST(ModbusCodec, ValidatesChannelsAndConfig) {
  std::string error;
  mb::ChannelConfig c = channel(10);
  EXPECT_TRUE(mb::validate(c, &error)) << error;
  c.scale = 0.0;
  EXPECT_FALSE(mb::validate(c, &error));
  c = channel(10);
  c.max = 200.0;  // beyond the binary angle's span
  EXPECT_FALSE(mb::validate(c, &error));
  EXPECT_NE(error.find("180"), std::string::npos) << error;
  c = channel(65535, mb::RegisterWidth::k32);
  EXPECT_FALSE(mb::validate(c, &error));

  mb::PollerConfig config;
  config.channels = {channel(0), channel(1)};
  config.channels[1].input = 1;
  EXPECT_TRUE(mb::validate(config, &error)) << error;
  config.channels[1].input = 0;
  EXPECT_FALSE(mb::validate(config, &error));
  EXPECT_NE(error.find("two channels"), std::string::npos) << error;
  config.channels[1].input = 1;
  config.link.tcp.host = "plc.local";
  EXPECT_FALSE(mb::validate(config, &error));
  config.link.tcp.host = "127.0.0.1";
  config.response_timeout_ns = 0;
  EXPECT_FALSE(mb::validate(config, &error));
  config.response_timeout_ns = 100'000'000;
  config.max_registers_per_read = 126;
  EXPECT_FALSE(mb::validate(config, &error));
  config.max_registers_per_read = 125;
  config.link.transport = mb::Transport::kRtu;
  EXPECT_FALSE(mb::validate(config, &error));  // no device
  config.link.rtu.device = "ttyS1";
  EXPECT_TRUE(mb::validate(config, &error)) << error;
  config.link.unit_id = 0;  // broadcast: no answers on a serial line
  EXPECT_FALSE(mb::validate(config, &error));
}

TEST(ModbusPlan, GroupsContiguousRegistersIntoFewestRequests) {
  std::vector<mb::ChannelConfig> channels;
  // Out of order on purpose: 16-bit at 3, 32-bit at 1..2, 16-bit at 0, 32-bit at 4..5.
  channels.push_back(channel(3));
  channels.push_back(channel(1, mb::RegisterWidth::k32));
  channels.push_back(channel(0));
  channels.push_back(channel(4, mb::RegisterWidth::k32));
  // Separate: a gap, and the input table.
  channels.push_back(channel(8));
  channels.push_back(channel(0, mb::RegisterWidth::k16, mb::RegisterTable::kInput));
  channels.push_back(channel(1, mb::RegisterWidth::k32, mb::RegisterTable::kInput));

  const std::vector<mb::ReadRequest> plan = mb::plan_requests(channels, 125, 0);
  ASSERT_EQ(plan.size(), 3u);
  EXPECT_EQ(plan[0].table, mb::RegisterTable::kHolding);
  EXPECT_EQ(plan[0].address, 0);
  EXPECT_EQ(plan[0].count, 6);
  EXPECT_EQ(plan[0].channels, (std::vector<uint16_t>{2, 1, 0, 3}));
  EXPECT_EQ(plan[1].address, 8);
  EXPECT_EQ(plan[1].count, 1);
  EXPECT_EQ(plan[2].table, mb::RegisterTable::kInput);
  EXPECT_EQ(plan[2].count, 3);

  // Reading across a 2-register gap is allowed with max_gap >= 2.
  EXPECT_EQ(mb::plan_requests(channels, 125, 2).size(), 2u);
}

TEST(ModbusPlan, SplitsAt125RegistersWithoutSplittingAValue) {
  std::vector<mb::ChannelConfig> channels;
  for (uint16_t a = 0; a < 124; ++a) channels.push_back(channel(a));
  channels.push_back(channel(124, mb::RegisterWidth::k32));  // would end at 126
  channels.push_back(channel(126));
  const std::vector<mb::ReadRequest> plan = mb::plan_requests(channels, 125, 0);
  ASSERT_EQ(plan.size(), 2u);
  EXPECT_EQ(plan[0].count, 124);
  EXPECT_EQ(plan[1].address, 124);
  EXPECT_EQ(plan[1].count, 3);

  // 300 contiguous registers: 125 + 125 + 50. A device limit of 60: 5 + 1.
  channels.clear();
  for (uint16_t a = 0; a < 300; ++a) channels.push_back(channel(a));
  EXPECT_EQ(mb::plan_requests(channels, 125, 0).size(), 3u);
  EXPECT_EQ(mb::plan_requests(channels, 60, 0).size(), 5u);
}

TEST(ModbusBackoff, DoublesUpToTheCapAndResets) {
  mb::Backoff b(20, 160);
  std::vector<uint64_t> waits;
  for (int i = 0; i < 6; ++i) waits.push_back(b.next());
  EXPECT_EQ(waits, (std::vector<uint64_t>{20, 40, 80, 160, 160, 160}));
  b.reset();
  EXPECT_EQ(b.current(), 0u);
  EXPECT_EQ(b.next(), 20u);
}

TEST(ModbusTripleBuffer, HandsOverOnlyTheLatestValue) {
  sinew::hal::TripleBuffer<int> tb(0);
  EXPECT_FALSE(tb.refresh());
  tb.back() = 1;
  tb.publish();
  tb.back() = 2;
  tb.publish();
  EXPECT_TRUE(tb.refresh());
  EXPECT_EQ(tb.front(), 2);
  EXPECT_FALSE(tb.refresh());
  EXPECT_EQ(tb.front(), 2);
}

TEST(ModbusTripleBuffer, NeverTearsUnderConcurrentUse) {
  // Every published array holds one value repeated: a torn read would mix two.
  using Block = std::array<uint64_t, 64>;
  sinew::hal::TripleBuffer<Block> tb(Block{});
  constexpr uint64_t kPublishes = 200000;
  std::atomic<bool> done{false};
  std::thread producer([&] {
    for (uint64_t v = 1; v <= kPublishes; ++v) {
      tb.back().fill(v);
      tb.publish();
    }
    done.store(true);
  });
  uint64_t last = 0, torn = 0, backwards = 0, seen = 0;
  while (true) {
    const bool finished = done.load();
    if (tb.refresh()) {
      const Block& b = tb.front();
      for (uint64_t x : b) torn += x != b[0] ? 1u : 0u;
      backwards += b[0] < last ? 1u : 0u;
      last = b[0];
      ++seen;
    }
    if (finished && !tb.refresh()) break;
  }
  producer.join();
  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(backwards, 0u);
  EXPECT_EQ(tb.front()[0], kPublishes);
  EXPECT_GT(seen, 0u);
}

TEST(ModbusStatusRegisters, EncodesTheDocumentedLayout) {
  const std::array<uint8_t, 3> inputs{0, sinew::hal::kJointStale, sinew::hal::kJointRejected};
  const std::array<hal::SourceState, 3> sources{hal::SourceState::kOk, hal::SourceState::kDown,
                                                hal::SourceState::kDegraded};
  mb::StatusUpdate u;
  u.tick = 0x0001000200030004u;
  u.last_step_ns = 70'000'123'456u;  // 70000123 us: needs both words
  u.stale_count = 1;
  u.input_status = inputs;
  u.source_states = sources;
  std::vector<uint16_t> image(mb::status_register_count(inputs.size()), 0xAAAA);
  mb::encode_status(u, 9, image);
  namespace r = mb::status_reg;
  EXPECT_EQ(image[r::kLayoutVersion], mb::kStatusLayout);
  EXPECT_EQ(image[r::kHeartbeat], 9);
  EXPECT_EQ((std::vector<uint16_t>(image.begin() + r::kTick, image.begin() + r::kTick + 4)),
            (std::vector<uint16_t>{1, 2, 3, 4}));
  EXPECT_EQ((uint32_t{image[r::kLastStepUs]} << 16) | image[r::kLastStepUs + 1], 70000123u);
  EXPECT_EQ(image[r::kStaleCount], 1);
  EXPECT_EQ(image[r::kInputCount], 3);
  EXPECT_EQ(image[r::kSourceCount], 3);
  EXPECT_EQ(image[r::kSourcesDown], 1);
  EXPECT_EQ(image[r::kSourcesDegraded], 1);
  EXPECT_EQ(image[r::kSourceState + 1], 2);
  EXPECT_EQ(image[r::kSourceState + 2], 1);
  EXPECT_EQ(image[r::kSourceState + 3], 0);  // unused source slots read 0
  EXPECT_EQ(image[r::kInputStatus + 1], sinew::hal::kJointStale);
  EXPECT_EQ(image[r::kInputStatus + 2], sinew::hal::kJointRejected);
}
