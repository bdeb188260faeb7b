// Frame log recovery: a copy truncated at every byte offset, and a copy with
// each single byte corrupted. The reader must return exactly the intact
// records before the damage, with their exact contents, and never more; for
// logs of plain and of compressed records alike.
#include "frame_log_fixture.hpp"
#include "hal/output/frame_log_format.hpp"

namespace sinew::test {
namespace {

using hal::output::kLogHeaderBytes;
using hal::output::LogStop;

class FrameLogDamageTest : public FrameLogTest, public testing::WithParamInterface<bool> {
 protected:
  void SetUp() override {
    hal::output::FrameLogOptions options;
    options.compress = GetParam();
    ends_ = write_frames(dir_.file("original.log"), 0, kFrames, options);
    original_ = read_bytes(dir_.file("original.log"));
    ASSERT_EQ(original_.size(), ends_.back());
  }

  // Records that end at or before `offset`.
  size_t complete_before(uint64_t offset) const {
    size_t n = 0;
    while (n < ends_.size() && ends_[n] <= offset) ++n;
    return n;
  }
  uint64_t record_start(size_t k) const { return k == 0 ? kLogHeaderBytes : ends_[k - 1]; }

  std::vector<uint64_t> ends_;
  std::vector<uint8_t> original_;
};

TEST_P(FrameLogDamageTest, TruncatedAtEveryByteRecoversTheCompleteFrames) {
  const std::string path = dir_.file("cut.log");
  for (size_t cut = 0; cut <= original_.size(); ++cut) {
    SCOPED_TRACE("cut at " + std::to_string(cut));
    write_bytes(path, original_.data(), cut);
    const ReadBack r = read_log(path);
    if (cut < kLogHeaderBytes) {
      EXPECT_FALSE(r.opened);
      continue;
    }
    ASSERT_TRUE(r.opened) << r.error;
    const size_t complete = complete_before(cut);
    expect_frames(r.poses, complete);
    const uint64_t intact_end = record_start(complete);
    EXPECT_EQ(r.stop_offset, intact_end);
    EXPECT_EQ(r.discarded, cut - intact_end);
    EXPECT_EQ(r.stop, cut == intact_end ? LogStop::kEnd : LogStop::kTornTail);
  }
}

TEST_P(FrameLogDamageTest, CorruptByteStopsAtItsRecord) {
  const std::string path = dir_.file("corrupt.log");
  for (const uint8_t flip : {uint8_t{0x01}, uint8_t{0x80}, uint8_t{0xFF}}) {
    for (size_t at = 0; at < original_.size(); ++at) {
      SCOPED_TRACE("byte " + std::to_string(at) + " xor " + std::to_string(flip));
      std::vector<uint8_t> bytes = original_;
      bytes[at] ^= flip;
      write_bytes(path, bytes.data(), bytes.size());
      const ReadBack r = read_log(path);
      if (at < kLogHeaderBytes) {  // the file header is checked as a whole
        EXPECT_FALSE(r.opened);
        continue;
      }
      ASSERT_TRUE(r.opened) << r.error;
      const size_t damaged = complete_before(at);  // index of the record holding the byte
      expect_frames(r.poses, damaged);
      EXPECT_EQ(r.stop_offset, record_start(damaged));
      EXPECT_EQ(r.discarded, original_.size() - record_start(damaged));
      EXPECT_TRUE(r.stop == LogStop::kBadRecordHeader || r.stop == LogStop::kBadChecksum ||
                  r.stop == LogStop::kTornTail)
          << hal::output::log_stop_name(r.stop);
    }
  }
}

TEST_P(FrameLogDamageTest, StopMessageSaysWhereAndWhy) {
  const std::string path = dir_.file("cut.log");
  write_bytes(path, original_.data(), ends_[1] + 7);
  hal::output::FrameLogReader reader;
  std::string error;
  ASSERT_TRUE(reader.open(path, &error)) << error;
  hal::output::DecodedPose pose;
  while (reader.next(&pose)) {
  }
  EXPECT_EQ(reader.records_read(), 2u);
  EXPECT_FALSE(reader.clean_end());
  EXPECT_EQ(reader.stop_message(), "torn-tail at offset " + std::to_string(ends_[1]) +
                                       ": record header cut short (7 of 16 bytes); 7 bytes discarded");
}

INSTANTIATE_TEST_SUITE_P(PlainAndCompressed, FrameLogDamageTest, testing::Bool(),
                         [](const testing::TestParamInfo<bool>& p) { return p.param ? "zstd" : "plain"; });

}  // namespace
}  // namespace sinew::test
