// Every receiver check of the default joint stream: the documented outcome
// and the counter it moves (docs/can-protocol.md, "Receiver checks").
#include "hal/can/joint_stream_decoder.hpp"

#include <gtest/gtest.h>

#include <string>

#include "hal/can/crc8_sae_j1850.hpp"
#include "hal/can/joint_stream_encoder.hpp"

namespace sinew::hal::can {
namespace {

constexpr uint64_t kStreamPeriod = 10'000'000;  // 10 ms
constexpr uint16_t kDataId = 0x5300;

class ClassicJoint : public ::testing::Test {
 protected:
  void SetUp() override {
    JointStreamConfig config = default_joint_stream_config(2, false, kStreamPeriod);
    config.frames[0].joints[0].min = -1000;
    config.frames[0].joints[0].max = 1000;
    std::string error;
    ASSERT_TRUE(decoder_.configure(config, &error)) << error;
  }

  FrameDecode send(uint8_t counter, int32_t value, uint64_t t_ns, uint8_t status = 0) {
    CanFrame f = encode_classic_joint_frame(kDefaultClassicBaseId, false, kDataId, {counter, status, value});
    f.timestamp_ns = t_ns;
    return feed(f);
  }
  FrameDecode feed(const CanFrame& f) {
    FrameDecode d;
    decoder_.decode(f, d);
    return d;
  }
  uint64_t rejected(RejectReason r) const { return decoder_.counters(0).rejected[reason_index(r)]; }

  JointStreamDecoder decoder_;
};

TEST_F(ClassicJoint, AcceptsAValidFrame) {
  const FrameDecode d = send(0, 500, 1234, kSampleSenderFault);
  ASSERT_EQ(d.sample_count, 1);
  EXPECT_EQ(d.rejection_count, 0);
  EXPECT_EQ(d.samples[0].input, 0);
  EXPECT_EQ(d.samples[0].value, 500);
  EXPECT_EQ(d.samples[0].timestamp_ns, 1234u);
  EXPECT_EQ(d.samples[0].status, kSampleSenderFault);  // the sender's status bits pass through
  EXPECT_EQ(decoder_.counters(0).accepted, 1u);
}

TEST_F(ClassicJoint, FirstFrameIsAcceptedWhateverItsCounter) {
  EXPECT_EQ(send(9, 1, 0).sample_count, 1);
  EXPECT_EQ(send(10, 2, kStreamPeriod).sample_count, 1);
}

TEST_F(ClassicJoint, BadCrcIsRejectedAndCountedAndLeavesTheCounterReference) {
  ASSERT_EQ(send(0, 1, 0).sample_count, 1);
  CanFrame f = encode_classic_joint_frame(kDefaultClassicBaseId, false, kDataId, {1, 0, 2});
  f.data[3] ^= 0x10;  // corrupted in transit
  f.timestamp_ns = kStreamPeriod;
  const FrameDecode d = feed(f);
  EXPECT_EQ(d.sample_count, 0);
  ASSERT_EQ(d.rejection_count, 1);
  EXPECT_EQ(d.rejections[0].input, 0);
  EXPECT_EQ(d.rejections[0].reason, RejectReason::kBadCrc);
  EXPECT_EQ(rejected(RejectReason::kBadCrc), 1u);
  // The corrupted record did not move the counter reference: counter 1 is still next.
  EXPECT_EQ(send(1, 3, 2 * kStreamPeriod).sample_count, 1);
}

TEST_F(ClassicJoint, RepeatedCounterIsRejectedAndCounted) {
  ASSERT_EQ(send(4, 1, 0).sample_count, 1);
  const FrameDecode d = send(4, 2, kStreamPeriod);
  EXPECT_EQ(d.sample_count, 0);
  ASSERT_EQ(d.rejection_count, 1);
  EXPECT_EQ(d.rejections[0].reason, RejectReason::kRepeatedCounter);
  EXPECT_EQ(rejected(RejectReason::kRepeatedCounter), 1u);
  EXPECT_EQ(send(5, 3, 2 * kStreamPeriod).sample_count, 1);
}

TEST_F(ClassicJoint, CounterJumpIsRejectedCountedAndResynchronises) {
  ASSERT_EQ(send(4, 1, 0).sample_count, 1);
  const FrameDecode d = send(6, 2, kStreamPeriod);  // one frame lost: delta 2 > max delta 1
  EXPECT_EQ(d.sample_count, 0);
  ASSERT_EQ(d.rejection_count, 1);
  EXPECT_EQ(d.rejections[0].reason, RejectReason::kCounterJump);
  EXPECT_EQ(rejected(RejectReason::kCounterJump), 1u);
  // The jumped counter is the new reference: the next consecutive record is accepted.
  EXPECT_EQ(send(7, 3, 2 * kStreamPeriod).sample_count, 1);
  EXPECT_EQ(decoder_.counters(0).accepted, 2u);
}

TEST_F(ClassicJoint, WrapFromFourteenToZeroIsDeltaOne) {
  ASSERT_EQ(send(13, 1, 0).sample_count, 1);
  EXPECT_EQ(send(14, 2, kStreamPeriod).sample_count, 1);
  EXPECT_EQ(send(0, 3, 2 * kStreamPeriod).sample_count, 1);
  EXPECT_EQ(decoder_.counters(0).rejected_total(), 0u);
}

TEST_F(ClassicJoint, OutOfRangeIsRejectedCountedButKeepsTheSequence) {
  ASSERT_EQ(send(0, 1000, 0).sample_count, 1);  // max is inclusive
  const FrameDecode d = send(1, 1001, kStreamPeriod);
  EXPECT_EQ(d.sample_count, 0);
  ASSERT_EQ(d.rejection_count, 1);
  EXPECT_EQ(d.rejections[0].reason, RejectReason::kOutOfRange);
  EXPECT_EQ(send(2, -1001, 2 * kStreamPeriod).rejections[0].reason, RejectReason::kOutOfRange);
  EXPECT_EQ(rejected(RejectReason::kOutOfRange), 2u);
  // The authentic out-of-range records advanced the counter: 3 is next.
  EXPECT_EQ(send(3, -1000, 3 * kStreamPeriod).sample_count, 1);
}

TEST_F(ClassicJoint, WrongLengthIsMalformed) {
  CanFrame f = encode_classic_joint_frame(kDefaultClassicBaseId, false, kDataId, {0, 0, 1});
  f.len = 7;
  const FrameDecode d = feed(f);
  EXPECT_EQ(d.sample_count, 0);
  ASSERT_EQ(d.rejection_count, 1);
  EXPECT_EQ(d.rejections[0].reason, RejectReason::kMalformed);
  f.len = 0;
  feed(f);
  EXPECT_EQ(rejected(RejectReason::kMalformed), 2u);
}

TEST_F(ClassicJoint, RemoteFrameAndCanFdFrameOnAClassicIdAreMalformed) {
  CanFrame remote;
  remote.id = kDefaultClassicBaseId;
  remote.kind = FrameKind::kRemote;
  remote.len = 8;
  EXPECT_EQ(feed(remote).rejections[0].reason, RejectReason::kMalformed);
  CanFrame fd = encode_classic_joint_frame(kDefaultClassicBaseId, false, kDataId, {0, 0, 1});
  fd.fd = true;
  EXPECT_EQ(feed(fd).rejections[0].reason, RejectReason::kMalformed);
  EXPECT_EQ(rejected(RejectReason::kMalformed), 2u);
}

TEST_F(ClassicJoint, CounterFifteenAndNonZeroReservedBytesAreMalformed) {
  CanFrame f = encode_classic_joint_frame(kDefaultClassicBaseId, false, kDataId, {15, 0, 1});
  EXPECT_EQ(feed(f).rejections[0].reason, RejectReason::kMalformed);
  f = encode_classic_joint_frame(kDefaultClassicBaseId, false, kDataId, {1, 0, 1});
  f.data[6] = 0xAA;
  f.data[0] = e2e_p01_crc(kDataId, std::span<const uint8_t>(f.data.data() + 1, 7));
  EXPECT_EQ(feed(f).rejections[0].reason, RejectReason::kMalformed);
  EXPECT_EQ(rejected(RejectReason::kMalformed), 2u);
}

TEST_F(ClassicJoint, UnknownIdIsCountedAgainstNoInput) {
  CanFrame f = encode_classic_joint_frame(0x7FF, false, kDataId, {0, 0, 1});
  const FrameDecode d = feed(f);
  EXPECT_EQ(d.sample_count, 0);
  ASSERT_EQ(d.rejection_count, 1);
  EXPECT_EQ(d.rejections[0].input, kNoInput);
  EXPECT_EQ(d.rejections[0].reason, RejectReason::kUnknownId);
  EXPECT_EQ(decoder_.unassigned().rejected[reason_index(RejectReason::kUnknownId)], 1u);
  EXPECT_EQ(decoder_.counters(0).rejected_total(), 0u);
}

TEST_F(ClassicJoint, ExtendedIdWithTheSameNumberIsAnotherFrame) {
  CanFrame f = encode_classic_joint_frame(kDefaultClassicBaseId, true, kDataId, {0, 0, 1});
  EXPECT_EQ(feed(f).rejections[0].reason, RejectReason::kUnknownId);
}

TEST_F(ClassicJoint, ErrorFramesAreIgnored) {
  CanFrame f;
  f.kind = FrameKind::kError;
  f.id = 0x40;
  f.len = 8;
  const FrameDecode d = feed(f);
  EXPECT_EQ(d.sample_count + d.rejection_count, 0);
  EXPECT_EQ(decoder_.unassigned().rejected_total(), 0u);
}

TEST_F(ClassicJoint, SilenceLongerThanTheTimeoutRestartsTheCounterCheck) {
  ASSERT_EQ(send(4, 1, 0).sample_count, 1);
  // Default timeout 1.5 x 10 ms: after 20 ms of silence the counter distance
  // means nothing (a rebooted sender starts anywhere), so 4 again is accepted.
  EXPECT_EQ(send(4, 2, 20'000'000).sample_count, 1);
  // Within the timeout a repeat is still a repeat.
  EXPECT_EQ(send(4, 3, 21'000'000).rejections[0].reason, RejectReason::kRepeatedCounter);
}

TEST_F(ClassicJoint, ChannelsCarryTheResolvedTimeout) {
  ASSERT_EQ(decoder_.channels().size(), 2u);
  EXPECT_EQ(decoder_.channels()[0].timeout_ns, 15'000'000u);
  ASSERT_EQ(decoder_.frame_ids().size(), 2u);
  EXPECT_EQ(decoder_.frame_ids()[1], (FrameId{kDefaultClassicBaseId + 1, false}));
  EXPECT_FALSE(decoder_.wants_fd());
}

TEST(JointStreamDecoderConfig, LargerMaxDeltaToleratesLostFrames) {
  JointStreamConfig config = default_joint_stream_config(1, false, kStreamPeriod);
  config.frames[0].joints[0].max_counter_delta = 3;
  JointStreamDecoder decoder;
  ASSERT_TRUE(decoder.configure(config, nullptr));
  FrameDecode d;
  decoder.decode(encode_classic_joint_frame(kDefaultClassicBaseId, false, kDataId, {0, 0, 1}), d);
  decoder.decode(encode_classic_joint_frame(kDefaultClassicBaseId, false, kDataId, {3, 0, 1}), d);
  EXPECT_EQ(d.sample_count, 1);
  decoder.decode(encode_classic_joint_frame(kDefaultClassicBaseId, false, kDataId, {7, 0, 1}), d);
  EXPECT_EQ(d.rejections[0].reason, RejectReason::kCounterJump);
}

TEST(JointStreamDecoderConfig, RejectsInconsistentConfigurations) {
  std::string error;
  JointStreamDecoder decoder;
  JointStreamConfig config = default_joint_stream_config(2, false, kStreamPeriod);
  config.frames[1].can_id = config.frames[0].can_id;
  EXPECT_FALSE(decoder.configure(config, &error));
  EXPECT_NE(error.find("identifier"), std::string::npos) << error;

  config = default_joint_stream_config(2, false, kStreamPeriod);
  config.frames[0].joints.push_back(config.frames[1].joints[0]);
  EXPECT_FALSE(decoder.configure(config, &error));

  config = default_joint_stream_config(9, true, kStreamPeriod);
  config.frames[0].joints.push_back(config.frames[1].joints[0]);  // 9 in one FD frame
  EXPECT_FALSE(decoder.configure(config, &error));

  config = default_joint_stream_config(2, false, kStreamPeriod);
  config.frames[1].joints[0].data_id = config.frames[0].joints[0].data_id;
  EXPECT_FALSE(decoder.configure(config, &error));
  EXPECT_NE(error.find("data ID"), std::string::npos) << error;

  config = default_joint_stream_config(2, false, kStreamPeriod);
  config.frames[1].joints[0].input = 0;
  EXPECT_FALSE(decoder.configure(config, &error));

  config = default_joint_stream_config(1, false, kStreamPeriod);
  config.frames[0].joints[0].min = 5;
  config.frames[0].joints[0].max = 4;
  EXPECT_FALSE(decoder.configure(config, &error));

  config = default_joint_stream_config(1, false, kStreamPeriod);
  config.frames[0].joints[0].max_counter_delta = 15;
  EXPECT_FALSE(decoder.configure(config, &error));
  config.frames[0].joints[0].max_counter_delta = 0;
  EXPECT_FALSE(decoder.configure(config, &error));

  config = default_joint_stream_config(1, false, kStreamPeriod);
  config.frames[0].can_id = 0x800;  // not 11-bit
  EXPECT_FALSE(decoder.configure(config, &error));
}

// --- packed CAN FD ---

class FdJoints : public ::testing::Test {
 protected:
  void SetUp() override {
    config_ = default_joint_stream_config(11, true, kStreamPeriod);  // 8 + 3 joints
    ASSERT_TRUE(decoder_.configure(config_, nullptr));
    ASSERT_TRUE(sender_.configure(config_, nullptr));
  }
  JointStreamConfig config_;
  JointStreamDecoder decoder_;
  JointStreamSender sender_;
};

TEST_F(FdJoints, DefaultLayoutPacksEightJointsPerFrame) {
  ASSERT_EQ(config_.frames.size(), 2u);
  EXPECT_EQ(config_.frames[0].can_id, kDefaultFdBaseId);
  EXPECT_EQ(config_.frames[1].can_id, kDefaultFdBaseId + 1);
  EXPECT_EQ(config_.frames[1].joints.size(), 3u);
  EXPECT_EQ(config_.frames[1].joints[2].data_id, kDefaultDataIdBase + 10);
  EXPECT_TRUE(decoder_.wants_fd());
}

TEST_F(FdJoints, AllSlotsDecode) {
  const int32_t values[8] = {10, -20, 30, -40, 50, -60, 70, INT32_MIN};
  CanFrame f = sender_.next(0, values, {}, 99);
  EXPECT_EQ(f.len, 64);
  FrameDecode d;
  decoder_.decode(f, d);
  ASSERT_EQ(d.sample_count, 8);
  for (size_t k = 0; k < 8; ++k) {
    EXPECT_EQ(d.samples[k].input, k);
    EXPECT_EQ(d.samples[k].value, values[k]);
    EXPECT_EQ(d.samples[k].timestamp_ns, 99u);
  }
}

TEST_F(FdJoints, PartialFrameUsesTheSmallestFdLength) {
  const int32_t values[3] = {1, 2, 3};
  CanFrame f = sender_.next(1, values);
  EXPECT_EQ(f.len, 24);
  FrameDecode d;
  decoder_.decode(f, d);
  ASSERT_EQ(d.sample_count, 3);
  EXPECT_EQ(d.samples[2].input, 10);
}

TEST_F(FdJoints, AFaultInOneSlotRejectsOnlyThatJoint) {
  const int32_t values[8] = {1, 2, 3, 4, 5, 6, 7, 8};
  CanFrame f = sender_.next(0, values);
  f.data[5 * 8 + 3] ^= 0x01;  // slot 5's value byte
  FrameDecode d;
  decoder_.decode(f, d);
  EXPECT_EQ(d.sample_count, 7);
  ASSERT_EQ(d.rejection_count, 1);
  EXPECT_EQ(d.rejections[0].input, 5);
  EXPECT_EQ(d.rejections[0].reason, RejectReason::kBadCrc);
  EXPECT_EQ(decoder_.counters(5).rejected[reason_index(RejectReason::kBadCrc)], 1u);
}

TEST_F(FdJoints, ShortFrameIsMalformedForEveryJointItCarries) {
  const int32_t values[8] = {};
  CanFrame f = sender_.next(0, values);
  f.len = 48;  // valid FD length, but only 6 slots
  FrameDecode d;
  decoder_.decode(f, d);
  EXPECT_EQ(d.sample_count, 0);
  ASSERT_EQ(d.rejection_count, 8);
  for (size_t k = 0; k < 8; ++k) {
    EXPECT_EQ(d.rejections[k].reason, RejectReason::kMalformed);
    EXPECT_EQ(decoder_.counters(static_cast<uint16_t>(k)).rejected[reason_index(RejectReason::kMalformed)], 1u);
  }
}

TEST_F(FdJoints, ClassicFrameOnAnFdIdIsMalformed) {
  const int32_t values[3] = {1, 2, 3};
  CanFrame f = sender_.next(1, values);
  f.fd = false;
  f.len = 8;
  FrameDecode d;
  decoder_.decode(f, d);
  EXPECT_EQ(d.rejection_count, 3);
  EXPECT_EQ(d.rejections[0].reason, RejectReason::kMalformed);
}

TEST(JointStreamSender, ManyFramesAcrossCounterWrapsAreAllAccepted) {
  const JointStreamConfig config = default_joint_stream_config(3, false, kStreamPeriod);
  JointStreamSender sender;
  JointStreamDecoder decoder;
  ASSERT_TRUE(sender.configure(config, nullptr));
  ASSERT_TRUE(decoder.configure(config, nullptr));
  FrameDecode d;
  for (int i = 0; i < 100; ++i) {
    for (size_t f = 0; f < sender.frame_count(); ++f) {
      const int32_t v = i * 1000 + static_cast<int32_t>(f);
      decoder.decode(sender.next(f, {&v, 1}, {}, static_cast<uint64_t>(i) * kStreamPeriod), d);
      ASSERT_EQ(d.sample_count, 1) << "frame " << f << " step " << i;
      EXPECT_EQ(d.samples[0].value, v);
    }
  }
  EXPECT_EQ(decoder.counters(2).accepted, 100u);
}

}  // namespace
}  // namespace sinew::hal::can
