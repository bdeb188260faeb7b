// Compressed frame logs (frame_compression.hpp): every frame back exactly,
// through keys and deltas; the size the transform must save on a smoothly
// moving mesh; appending; refusing to mix plain and compressed records; a
// record whose checksum is right but whose content is not is reported as
// damage; and a write path that does not allocate.
#include <zstd.h>

#include <cmath>
#include <filesystem>

#include "frame_log_fixture.hpp"
#include "hal/output/frame_compression.hpp"
#include "hal/output/frame_log_format.hpp"
#include "tests/support/alloc_guard.hpp"

namespace sinew::test {
namespace {

using hal::output::FrameLogOptions;
using hal::output::FrameLogWriter;
using hal::output::LogStop;

FrameLogOptions zstd_options(uint32_t key_every = 1000) {
  FrameLogOptions o;
  o.compress = true;
  o.key_every_frames = key_every;
  return o;
}

TEST_F(FrameLogTest, CompressedRoundTripsEveryFrameThroughKeysAndDeltas) {
  for (const uint32_t key_every : {1u, 2u, 1000u}) {
    SCOPED_TRACE("key every " + std::to_string(key_every));
    std::string name = std::to_string(key_every);  // not "z" + ...: GCC 12's -Wrestrict false positive (PR 105651)
    name.insert(0, 1, 'z');
    name += ".log";
    const std::string path = dir_.file(name);
    write_frames(path, 0, kFrames, zstd_options(key_every));
    const ReadBack r = read_log(path);
    ASSERT_TRUE(r.opened) << r.error;
    expect_frames(r.poses, kFrames);  // frame 2 has no normals: a key between deltas
    EXPECT_EQ(r.stop, LogStop::kEnd);
  }
}

// A mesh moving smoothly at 1 kHz: consecutive frames differ by a few
// hundred units of a Q12.20 word, so after the delta the two high byte planes
// are all 0x00 or 0xFF, which zstd stores in a few bytes; at most the two low
// planes remain, so the records must come out at most half the raw size.
TEST(FrameLogCompression, SmoothMotionAtLeastHalvesTheLog) {
  TempDir dir;
  constexpr uint32_t kVertices = 2000, kInputs = 4;
  TestPose pose(kVertices, kInputs, true);
  hal::PoseFrame frame = pose.frame();
  std::vector<int32_t> xyz[6];
  for (auto& a : xyz) a.resize(kVertices);
  for (int c = 0; c < 3; ++c) {
    frame.position[c] = xyz[c].data();
    frame.normal[c] = xyz[3 + c].data();
  }
  uint64_t raw = 0, packed = 0;
  for (const bool compress : {false, true}) {
    FrameLogOptions options;
    options.compress = compress;
    FrameLogWriter writer;
    std::string error;
    ASSERT_TRUE(writer.open(dir.file(compress ? "z.log" : "raw.log"), pose.shape(), options, &error)) << error;
    for (uint64_t t = 0; t < 200; ++t) {
      frame.tick = t;
      frame.timestamp_ns = t * 1000000;
      const double phase = 2.0 * M_PI * static_cast<double>(t) / 1000.0;  // a 1 Hz swing
      for (uint32_t v = 0; v < kVertices; ++v)
        for (int c = 0; c < 6; ++c)
          xyz[c][v] = static_cast<int32_t>(std::lround((1 << 20) * (0.3 * std::sin(phase + 0.001 * v + c))));
      ASSERT_TRUE(writer.write(frame));
    }
    (compress ? packed : raw) = writer.file_bytes();
  }
  std::printf("smooth motion, 200 frames of %u vertices: %llu bytes plain, %llu compressed (%.1fx)\n", kVertices,
              static_cast<unsigned long long>(raw), static_cast<unsigned long long>(packed),
              static_cast<double>(raw) / static_cast<double>(packed));
  EXPECT_LT(packed, raw / 2);
}

TEST_F(FrameLogTest, CompressedAppendStartsWithAKey) {
  const std::string path = dir_.file("a.log");
  write_frames(path, 0, 2, zstd_options());
  {
    FrameLogWriter writer;
    std::string error;
    ASSERT_TRUE(writer.open(path, shape_, zstd_options(), &error)) << error;
    EXPECT_TRUE(writer.stats().appended);
    for (uint64_t t = 2; t < kFrames; ++t) ASSERT_TRUE(writer.write(poses_[t]->frame()));
  }
  const ReadBack r = read_log(path);
  ASSERT_TRUE(r.opened) << r.error;
  expect_frames(r.poses, kFrames);
}

TEST_F(FrameLogTest, RefusesToMixPlainAndCompressedRecords) {
  const std::string plain = dir_.file("plain.log"), packed = dir_.file("packed.log");
  write_frames(plain, 0, 1);
  write_frames(packed, 0, 1, zstd_options());
  FrameLogWriter writer;
  std::string error;
  EXPECT_FALSE(writer.open(plain, shape_, zstd_options(), &error));
  EXPECT_NE(error.find("not compressed, the sink's are"), std::string::npos) << error;
  EXPECT_FALSE(writer.open(packed, shape_, {}, &error));
  EXPECT_NE(error.find("its records are compressed"), std::string::npos) << error;
}

TEST_F(FrameLogTest, RefusesACompressionLevelOutOfRange) {
  FrameLogOptions options = zstd_options();
  options.compression_level = 23;
  FrameLogWriter writer;
  std::string error;
  EXPECT_FALSE(writer.open(dir_.file("a.log"), shape_, options, &error));
  EXPECT_NE(error.find("compression level 23"), std::string::npos) << error;
}

// Records whose checksum matches but whose content is not a valid compressed
// frame (as a writer bug or a forger would make them) stop the reader there.
TEST_F(FrameLogTest, CompressedRecordsThatDoNotDecodeAreDamage) {
  const std::vector<uint8_t> garbage_frame = {0x28, 0xB5, 0x2F, 0xFD, 0x20, 0x05, 0x29, 0x00, 1, 2, 3};
  struct Case {
    const char* name;
    std::vector<uint8_t> record;
    const char* why;
  };
  const std::vector<Case> cases = {
      {"unknown kind", {7, 0x28, 0xB5}, "unknown kind 7"},
      {"not zstd", {0, 'n', 'o', 't', ' ', 'z', 's', 't', 'd'}, "not a zstd frame"},
      {"delta first", {1}, "delta record without a record before it"},
  };
  // The last case: a real delta record, copied to the front of another log.
  const std::string source = dir_.file("source.log");
  const std::vector<uint64_t> ends = write_frames(source, 0, 2, zstd_options());
  const std::vector<uint8_t> bytes = read_bytes(source);
  std::vector<uint8_t> delta(bytes.begin() + static_cast<std::ptrdiff_t>(ends[0] + 16), bytes.end());
  ASSERT_EQ(delta[0], hal::output::kRecordKindDelta);
  std::vector<Case> all = cases;
  all[2].record = delta;
  for (const Case& c : all) {
    SCOPED_TRACE(c.name);
    std::vector<uint8_t> file = hal::output::encode_log_preamble(shape_, "", true);
    const size_t at = file.size();
    file.resize(at + 16 + c.record.size());
    hal::output::encode_record_header(c.record, file.data() + at);
    std::copy(c.record.begin(), c.record.end(), file.begin() + static_cast<std::ptrdiff_t>(at + 16));
    const std::string path = dir_.file("forged.log");
    write_bytes(path, file.data(), file.size());
    hal::output::FrameLogReader reader;
    std::string error;
    ASSERT_TRUE(reader.open(path, &error)) << error;
    EXPECT_TRUE(reader.compressed());
    hal::output::DecodedPose pose;
    EXPECT_FALSE(reader.next(&pose));
    EXPECT_EQ(reader.stop(), LogStop::kBadPayload);
    EXPECT_NE(reader.stop_message().find(c.why), std::string::npos) << reader.stop_message();
  }
}

// A compressed log's header can claim frames of gigabytes in a file of a
// few dozen bytes: the reader's buffers are bounded by what the file's
// bytes can decode to (RFC 8878: at most 32 768 bytes a byte), not by the
// claim. Found by frame_log_reader_fuzz (out of memory at open).
TEST_F(FrameLogTest, AHugeCompressedShapeInAShortFileAllocatesNoMoreThanItCanDecode) {
  hal::output::FrameShape huge;
  huge.vertex_count = 20'000'000;
  huge.input_count = 16;
  huge.normals = true;
  const uint64_t claimed = hal::output::max_pose_payload_bytes(huge);
  ASSERT_GT(claimed, uint64_t{400} << 20);
  std::vector<uint8_t> bytes(hal::output::kLogHeaderBytes + 40, 0);
  hal::output::encode_log_header(huge, true, bytes.data());
  const std::string path = dir_.file("claims.log");
  write_bytes(path, bytes.data(), bytes.size());
  const ReadBack r = read_log(path);
  ASSERT_TRUE(r.opened) << r.error;
  EXPECT_TRUE(r.poses.empty());
  EXPECT_NE(r.stop, LogStop::kEnd);

  hal::output::FrameDecompressor d;
  std::string error;
  ASSERT_TRUE(d.init(static_cast<size_t>(claimed), 40, &error)) << error;
  EXPECT_LE(d.capacity(), 40u * 32768u);
  ASSERT_TRUE(d.init(1000, 40, &error)) << error;
  EXPECT_EQ(d.capacity(), 1000u);  // a frame smaller than the bound is held whole
}

// The bound against zstd itself: its best ratio, on a megabyte of one byte
// at the highest level, stays within 32 768.
TEST(FrameLogCompression, ZstdBestRatioIsWithinTheDecodeBound) {
  const std::vector<uint8_t> ones(1 << 20, 0x5A);
  std::vector<uint8_t> packed(ZSTD_compressBound(ones.size()));
  const size_t z = ZSTD_compress(packed.data(), packed.size(), ones.data(), ones.size(), ZSTD_maxCLevel());
  ASSERT_FALSE(ZSTD_isError(z));
  EXPECT_GE(hal::output::zstd_max_decoded_bytes(z), ones.size()) << z << " bytes";
}

TEST_F(FrameLogTest, CompressedWritePathDoesNotAllocate) {
  FrameLogWriter writer;
  std::string error;
  ASSERT_TRUE(writer.open(dir_.file("a.log"), shape_, zstd_options(100), &error)) << error;
  TestPose pose(kVertices, kInputs, true);
  AllocationCounter counter;
  for (uint64_t t = 0; t < 500; ++t) {
    pose.set_tick(t);
    ASSERT_TRUE(writer.write(pose.frame()));
  }
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_EQ(writer.stats().frames_written, 500u);
}

}  // namespace
}  // namespace sinew::test
