#include "hal/can/joint_record.hpp"

#include <gtest/gtest.h>

#include <array>

#include "hal/can/crc8_sae_j1850.hpp"

namespace sinew::hal::can {
namespace {

using Bytes = std::array<uint8_t, kJointRecordSize>;

Bytes encode(uint16_t data_id, uint8_t counter, uint8_t status, int32_t value) {
  Bytes b{};
  encode_joint_record(data_id, {counter, status, value}, b);
  return b;
}

TEST(JointRecord, ByteLayout) {
  const Bytes b = encode(0x5300, 9, 0x1, 0x12345678);
  EXPECT_EQ(b[1], 0x19);  // status in the high nibble, counter in the low
  EXPECT_EQ(b[2], 0x78);  // value little-endian
  EXPECT_EQ(b[3], 0x56);
  EXPECT_EQ(b[4], 0x34);
  EXPECT_EQ(b[5], 0x12);
  EXPECT_EQ(b[6], 0x00);
  EXPECT_EQ(b[7], 0x00);
  EXPECT_EQ(b[0], e2e_p01_crc(0x5300, std::span<const uint8_t>(b).subspan(1)));
}

TEST(JointRecord, MatchesTheE2eProfile1SpecificationExample) {
  // Data ID 0x123, zero payload: the profile 1 example frames byte for byte.
  EXPECT_EQ(encode(0x123, 0, 0, 0), (Bytes{0xCC, 0x00, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(encode(0x123, 1, 0, 0), (Bytes{0x91, 0x01, 0, 0, 0, 0, 0, 0}));
}

TEST(JointRecord, NegativeValueRoundTrips) {
  const Bytes b = encode(7, 3, 0, -1073741824);  // -90 degrees
  EXPECT_EQ(b[2], 0x00);
  EXPECT_EQ(b[5], 0xC0);
  JointRecord r;
  ASSERT_EQ(decode_joint_record(7, b, r), RecordCheck::kOk);
  EXPECT_EQ(r.value, -1073741824);
  EXPECT_EQ(r.counter, 3);
  EXPECT_EQ(r.status, 0);
}

TEST(JointRecord, ExtremeValuesRoundTrip) {
  for (int32_t v : {INT32_MIN, INT32_MAX, 0, -1, 1}) {
    JointRecord r;
    ASSERT_EQ(decode_joint_record(1, encode(1, 0, 0, v), r), RecordCheck::kOk);
    EXPECT_EQ(r.value, v);
  }
}

TEST(JointRecord, AnySingleBitFlipIsCaughtByTheCrc) {
  const Bytes good = encode(0x5305, 4, 0, 123456789);
  for (size_t bit = 0; bit < 64; ++bit) {
    Bytes b = good;
    b[bit / 8] = static_cast<uint8_t>(b[bit / 8] ^ (1u << (bit % 8)));
    JointRecord r;
    EXPECT_EQ(decode_joint_record(0x5305, b, r), RecordCheck::kBadCrc) << "bit " << bit;
  }
}

TEST(JointRecord, WrongDataIdIsABadCrc) {
  JointRecord r;
  EXPECT_EQ(decode_joint_record(0x5306, encode(0x5305, 4, 0, 42), r), RecordCheck::kBadCrc);
}

TEST(JointRecord, CounterFifteenIsInvalidEvenWithAGoodCrc) {
  JointRecord r;
  EXPECT_EQ(decode_joint_record(3, encode(3, 15, 0, 42), r), RecordCheck::kInvalidCounter);
}

TEST(JointRecord, ReservedBytesMustBeZero) {
  Bytes b = encode(3, 1, 0, 42);
  b[7] = 0x01;
  b[0] = e2e_p01_crc(3, std::span<const uint8_t>(b).subspan(1));  // a correctly protected but non-zero reserved byte
  JointRecord r;
  EXPECT_EQ(decode_joint_record(3, b, r), RecordCheck::kReservedNotZero);
}

TEST(JointRecord, AliveCounterDeltaWrapsAtFifteen) {
  EXPECT_EQ(alive_counter_delta(14, 0), 1);
  EXPECT_EQ(alive_counter_delta(0, 1), 1);
  EXPECT_EQ(alive_counter_delta(5, 5), 0);
  EXPECT_EQ(alive_counter_delta(13, 1), 3);
  EXPECT_EQ(alive_counter_delta(0, 14), 14);
}

}  // namespace
}  // namespace sinew::hal::can
