// Third-party encoder signals: raw bits → physical → range → engine units.
#include "hal/can/signal_decoder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace sinew::hal::can {
namespace {

CanFrame frame(uint32_t id, std::initializer_list<int> bytes, bool extended = false) {
  CanFrame f;
  f.id = id;
  f.extended = extended;
  for (int b : bytes) f.data[f.len++] = static_cast<uint8_t>(b);
  return f;
}

// An absolute encoder: 16-bit Intel unsigned, 0.01 deg per count, offset -180.
SignalSpec intel_encoder() {
  SignalSpec s;
  s.can_id = 0x321;
  s.start_bit = 8;
  s.length = 16;
  s.scale = 0.01;
  s.offset = -180.0;
  s.min = -120.0;
  s.max = 120.0;
  s.input = 2;
  s.period_ns = 4'000'000;
  return s;
}

// A Motorola signed 12-bit angle, 0.1 deg per count, starting mid-byte.
SignalSpec motorola_encoder() {
  SignalSpec s;
  s.can_id = 0x18FF0102;
  s.extended = true;
  s.start_bit = 11;  // bits 3..0 of byte 1, then byte 2
  s.length = 12;
  s.byte_order = ByteOrder::kMotorola;
  s.is_signed = true;
  s.scale = 0.1;
  s.min = -90.0;
  s.max = 90.0;
  s.input = 5;
  return s;
}

class SignalDecoderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    ASSERT_TRUE(decoder_.configure({intel_encoder(), motorola_encoder()}, &error)) << error;
  }
  FrameDecode feed(const CanFrame& f) {
    FrameDecode d;
    decoder_.decode(f, d);
    return d;
  }
  SignalDecoder decoder_;
};

TEST_F(SignalDecoderTest, IntelUnsignedWithOffset) {
  // raw 27000 = 0x6978 little-endian in bytes 1..2 → 270.00 - 180 = 90 degrees.
  const FrameDecode d = feed(frame(0x321, {0xEE, 0x78, 0x69}));
  ASSERT_EQ(d.sample_count, 1);
  EXPECT_EQ(d.samples[0].input, 2);
  EXPECT_EQ(d.samples[0].value, 1 << 30);
}

TEST_F(SignalDecoderTest, MotorolaSignedAcrossBytes) {
  // raw 0xE3E (12-bit two's complement) = -450 → -45.0 degrees → -2^29.
  const FrameDecode d = feed(frame(0x18FF0102, {0xFF, 0xAE, 0x3E}, true));
  ASSERT_EQ(d.sample_count, 1) << (d.rejection_count ? static_cast<int>(d.rejections[0].reason) : -1);
  EXPECT_EQ(d.samples[0].input, 5);
  EXPECT_EQ(d.samples[0].value, -(1 << 29));
}

TEST_F(SignalDecoderTest, OutOfRangeIsRejectedAndCounted) {
  // raw 30500 = 0x7724 → 125 degrees > 120.
  const FrameDecode d = feed(frame(0x321, {0, 0x24, 0x77}));
  EXPECT_EQ(d.sample_count, 0);
  ASSERT_EQ(d.rejection_count, 1);
  EXPECT_EQ(d.rejections[0].input, 2);
  EXPECT_EQ(d.rejections[0].reason, RejectReason::kOutOfRange);
  EXPECT_EQ(decoder_.counters(2).rejected[reason_index(RejectReason::kOutOfRange)], 1u);
}

TEST_F(SignalDecoderTest, FrameTooShortIsMalformed) {
  const FrameDecode d = feed(frame(0x321, {0, 0x24}));
  ASSERT_EQ(d.rejection_count, 1);
  EXPECT_EQ(d.rejections[0].reason, RejectReason::kMalformed);
  EXPECT_EQ(decoder_.counters(2).rejected[reason_index(RejectReason::kMalformed)], 1u);
}

TEST_F(SignalDecoderTest, RemoteFrameIsMalformed) {
  CanFrame f = frame(0x321, {});
  f.kind = FrameKind::kRemote;
  f.len = 3;
  EXPECT_EQ(feed(f).rejections[0].reason, RejectReason::kMalformed);
}

TEST_F(SignalDecoderTest, UnknownIdIsCounted) {
  const FrameDecode d = feed(frame(0x322, {1, 2, 3}));
  ASSERT_EQ(d.rejection_count, 1);
  EXPECT_EQ(d.rejections[0].reason, RejectReason::kUnknownId);
  EXPECT_EQ(decoder_.unassigned().rejected[reason_index(RejectReason::kUnknownId)], 1u);
  // Same number, standard format: not the extended encoder.
  EXPECT_EQ(feed(frame(0x102, {0, 0xA0, 0x00})).rejections[0].reason, RejectReason::kUnknownId);
}

TEST_F(SignalDecoderTest, TimeoutDefaultsToOneAndAHalfPeriods) {
  ASSERT_EQ(decoder_.channels().size(), 2u);
  bool found = false;
  for (const ChannelInfo& c : decoder_.channels()) {
    if (c.input == 2) {
      EXPECT_EQ(c.timeout_ns, 6'000'000u);
      found = true;
    }
  }
  EXPECT_TRUE(found);
  EXPECT_FALSE(decoder_.wants_fd());
}

TEST(SignalDecoder, SeveralSignalsInOneFrame) {
  SignalSpec a;
  a.can_id = 0x200;
  a.start_bit = 0;
  a.length = 32;
  a.is_signed = true;
  a.scale = 1.0 / 1048576.0;
  a.min = -10.0;
  a.max = 10.0;
  a.unit = PhysicalUnit::kRigUnits;
  a.input = 0;
  SignalSpec b = a;
  b.start_bit = 32;
  b.input = 1;
  SignalDecoder decoder;
  ASSERT_TRUE(decoder.configure({a, b}, nullptr));
  // 0x00180000 = 1.5 units; 0xFFF00000 = -1.0 units, Q12.20 passes through.
  FrameDecode d;
  decoder.decode(frame(0x200, {0x00, 0x00, 0x18, 0x00, 0x00, 0x00, 0xF0, 0xFF}), d);
  ASSERT_EQ(d.sample_count, 2);
  EXPECT_EQ(d.samples[0].value, 3 << 19);
  EXPECT_EQ(d.samples[1].value, -(1 << 20));
}

TEST(SignalDecoder, SixtyFourBitSignedSignal) {
  SignalSpec s;
  s.can_id = 0x300;
  s.start_bit = 7;
  s.length = 64;
  s.byte_order = ByteOrder::kMotorola;
  s.is_signed = true;
  s.scale = 1e-9;  // nano-degrees
  s.min = -180.0;
  s.max = 180.0;
  SignalDecoder decoder;
  ASSERT_TRUE(decoder.configure({s}, nullptr));
  // -45e9 nano-degrees = 0xFFFFFFF585CA7E00 big-endian.
  FrameDecode d;
  decoder.decode(frame(0x300, {0xFF, 0xFF, 0xFF, 0xF5, 0x85, 0xCA, 0x7E, 0x00}), d);
  ASSERT_EQ(d.sample_count, 1);
  EXPECT_EQ(d.samples[0].value, -(1 << 29));
}

TEST(SignalDecoder, SignalsBeyondEightBytesNeedCanFd) {
  SignalSpec s = intel_encoder();
  s.start_bit = 100;
  SignalDecoder decoder;
  ASSERT_TRUE(decoder.configure({s}, nullptr));
  EXPECT_TRUE(decoder.wants_fd());
}

TEST(SignalDecoder, ConfigurationRefusesWhatCouldMisbehave) {
  SignalDecoder decoder;
  std::string error;
  auto refused = [&](SignalSpec s) { return !decoder.configure({s}, &error); };
  SignalSpec s = intel_encoder();
  s.length = 0;
  EXPECT_TRUE(refused(s));
  s = intel_encoder();
  s.length = 65;
  EXPECT_TRUE(refused(s));
  s = intel_encoder();
  s.scale = 0.0;
  EXPECT_TRUE(refused(s));
  s.scale = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(refused(s));
  s = intel_encoder();
  s.offset = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(refused(s));
  s = intel_encoder();
  s.length = 64;
  s.start_bit = 0;
  s.scale = 1e300;  // 2^64 x 1e300 overflows: an infinite physical value would be possible
  EXPECT_TRUE(refused(s));
  EXPECT_NE(error.find("overflow"), std::string::npos) << error;
  s = intel_encoder();
  s.min = 0.0;
  s.max = 0.0;
  EXPECT_TRUE(refused(s));
  EXPECT_NE(error.find("[0|0]"), std::string::npos) << error;
  s = intel_encoder();
  s.min = 10.0;
  s.max = -10.0;
  EXPECT_TRUE(refused(s));
  s = intel_encoder();
  s.unit = PhysicalUnit::kRigUnits;
  s.max = 5000.0;  // beyond Q12.20
  EXPECT_TRUE(refused(s));
  s = intel_encoder();
  s.start_bit = 505;  // runs past byte 63
  EXPECT_TRUE(refused(s));
  s = intel_encoder();
  s.can_id = 0x800;
  EXPECT_TRUE(refused(s));
  SignalSpec dup = intel_encoder();
  dup.can_id = 0x400;
  EXPECT_FALSE(decoder.configure({intel_encoder(), dup}, &error));  // one input, two signals
}

// NaN is impossible by construction: for accepted specs every raw value gives
// a finite physical value, and the decoder never emits anything else.
TEST(SignalDecoder, EveryRawValueOfAValidSpecIsFinite) {
  uint64_t state = 0x243F6A8885A308D3u;
  auto next = [&] {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  for (int i = 0; i < 2000; ++i) {
    SignalSpec s;
    s.length = static_cast<uint8_t>(1 + next() % 64);
    s.is_signed = (next() & 1) != 0;
    s.scale = std::ldexp(1.0 + static_cast<double>(next() % 1000) / 100.0, static_cast<int>(next() % 1800) - 900);
    if ((next() & 1) != 0) s.scale = -s.scale;
    s.offset = std::ldexp(static_cast<double>(next() % 1000), static_cast<int>(next() % 1800) - 900);
    s.min = -1.0;
    s.max = 1.0;
    if (!validate(s, nullptr)) continue;
    for (uint64_t raw : {uint64_t{0}, ~uint64_t{0}, next(), uint64_t{1} << (s.length - 1)}) {
      const uint64_t field = s.length == 64 ? raw : raw & ((uint64_t{1} << s.length) - 1);
      ASSERT_TRUE(std::isfinite(physical_value(s, field))) << "scale " << s.scale << " offset " << s.offset;
    }
  }
}

}  // namespace
}  // namespace sinew::hal::can
