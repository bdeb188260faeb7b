// Frame log: round trip, append, refusal of incompatible or damaged logs,
// fsync policy, locking, and an allocation-free write path.
#include <fcntl.h>
#include <unistd.h>

#include <filesystem>

#include "frame_log_fixture.hpp"
#include "hal/output/frame_log_format.hpp"
#include "hal/output/frame_log_reader.hpp"
#include "hal/output/frame_log_scan.hpp"
#include "tests/support/alloc_guard.hpp"

namespace sinew::test {
namespace {

using hal::output::FrameLogOptions;
using hal::output::FrameLogWriter;
using hal::output::kLogHeaderBytes;
using hal::output::LogStop;

TEST_F(FrameLogTest, RoundTripsEveryFrame) {
  const std::string path = dir_.file("a.log");
  const std::vector<uint64_t> ends = write_frames(path, 0, kFrames);
  EXPECT_EQ(std::filesystem::file_size(path), ends.back());
  const ReadBack r = read_log(path);
  ASSERT_TRUE(r.opened) << r.error;
  expect_frames(r.poses, kFrames);
  EXPECT_EQ(r.stop, LogStop::kEnd);
  EXPECT_EQ(r.discarded, 0u);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

TEST_F(FrameLogTest, AppendsToAnExistingLog) {
  const std::string path = dir_.file("a.log");
  write_frames(path, 0, 3);
  FrameLogWriter writer;
  std::string error;
  ASSERT_TRUE(writer.open(path, shape_, {}, &error)) << error;
  EXPECT_TRUE(writer.stats().appended);
  EXPECT_EQ(writer.stats().tail_bytes_cut, 0u);
  for (uint64_t t = 3; t < kFrames; ++t) EXPECT_TRUE(writer.write(poses_[t]->frame()));
  writer.close();
  const ReadBack r = read_log(path);
  expect_frames(r.poses, kFrames);
  EXPECT_EQ(r.stop, LogStop::kEnd);
}

TEST_F(FrameLogTest, RefusesAnIncompatibleLog) {
  const std::string path = dir_.file("a.log");
  write_frames(path, 0, 2);
  hal::output::FrameShape other = shape_;
  other.vertex_count += 1;
  FrameLogWriter writer;
  std::string error;
  EXPECT_FALSE(writer.open(path, other, {}, &error));
  EXPECT_NE(error.find("incompatible"), std::string::npos) << error;
  EXPECT_NE(error.find("vertex count 10 in the log, 11 now"), std::string::npos) << error;
  EXPECT_EQ(read_log(path).poses.size(), 2u);  // untouched
}

TEST_F(FrameLogTest, RefusesAFileThatIsNotALog) {
  const std::string path = dir_.file("other.bin");
  const std::string text = "this is not a frame log, just some text that is long enough";
  write_bytes(path, reinterpret_cast<const uint8_t*>(text.data()), text.size());
  FrameLogWriter writer;
  std::string error;
  EXPECT_FALSE(writer.open(path, shape_, {}, &error));
  EXPECT_NE(error.find("not a frame log"), std::string::npos) << error;
  const ReadBack r = read_log(path);
  EXPECT_FALSE(r.opened);
  EXPECT_EQ(read_bytes(path).size(), text.size());
}

// A header is 40 bytes, but its counts may describe records of up to 1 GiB:
// the scanner's record buffer must follow the file, not the claim (found by
// frame_log_reader_fuzz: a 52-byte file made the reader allocate 400 MB).
TEST_F(FrameLogTest, AHugeShapeInAShortFileAllocatesNoMoreThanTheFile) {
  hal::output::FrameShape huge;
  huge.vertex_count = 20'000'000;
  huge.input_count = 16;
  huge.normals = true;
  ASSERT_GT(hal::output::max_record_bytes(huge), uint64_t{400} << 20);
  std::vector<uint8_t> bytes(kLogHeaderBytes + 12, 0);
  hal::output::encode_log_header(huge, false, bytes.data());
  const std::string path = dir_.file("claims.log");
  write_bytes(path, bytes.data(), bytes.size());

  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  hal::output::RecordScanner scan;
  scan.start(fd, bytes.size(), huge);
  EXPECT_LE(scan.buffer_bytes(), bytes.size());
  std::span<const uint8_t> payload;
  EXPECT_FALSE(scan.next(&payload));
  EXPECT_EQ(scan.stop(), LogStop::kTornTail);
  ::close(fd);

  const ReadBack r = read_log(path);
  ASSERT_TRUE(r.opened) << r.error;
  EXPECT_TRUE(r.poses.empty());
  EXPECT_EQ(r.stop, LogStop::kTornTail);
  EXPECT_EQ(r.discarded, 12u);
}

// The scanner still holds the largest record when the file is long enough.
TEST_F(FrameLogTest, RecordBufferHoldsTheLargestRecordOfALongFile) {
  const std::string path = dir_.file("a.log");
  write_frames(path, 0, kFrames);
  const uint64_t size = std::filesystem::file_size(path);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  hal::output::RecordScanner scan;
  scan.start(fd, size, shape_);
  EXPECT_EQ(scan.buffer_bytes(), hal::output::max_record_bytes(shape_));
  std::span<const uint8_t> payload;
  uint64_t records = 0;
  while (scan.next(&payload)) ++records;
  EXPECT_EQ(records, kFrames);
  EXPECT_EQ(scan.stop(), LogStop::kEnd);
  ::close(fd);
}

TEST_F(FrameLogTest, RefusesANewerVersion) {
  const std::string path = dir_.file("a.log");
  write_frames(path, 0, 1);
  std::vector<uint8_t> bytes = read_bytes(path);
  bytes[8] = 3;  // version field; the header checksum is not even reached
  write_bytes(path, bytes.data(), bytes.size());
  const ReadBack r = read_log(path);
  EXPECT_FALSE(r.opened);
  EXPECT_NE(r.error.find("version 3"), std::string::npos) << r.error;
}

// A version-2 log carries a metadata block (a recording's run description)
// between its header and its records: read back exactly, checked by its own
// checksum, and an append must describe the same content.
TEST_F(FrameLogTest, MetadataIsKeptCheckedAndMustMatchToAppend) {
  const std::string path = dir_.file("meta.log");
  FrameLogOptions options;
  options.metadata = "sinew-recording 1\nrig_xxh64 = 0123456789abcdef\n";
  write_frames(path, 0, 3, options);
  {
    hal::output::FrameLogReader reader;
    std::string error;
    ASSERT_TRUE(reader.open(path, &error)) << error;
    EXPECT_EQ(reader.metadata(), options.metadata);
  }
  FrameLogWriter writer;
  std::string error;
  ASSERT_TRUE(writer.open(path, shape_, options, &error)) << error;
  for (uint64_t t = 3; t < kFrames; ++t) EXPECT_TRUE(writer.write(poses_[t]->frame()));
  writer.close();
  const ReadBack r = read_log(path);
  expect_frames(r.poses, kFrames);
  EXPECT_EQ(r.stop, LogStop::kEnd);

  FrameLogOptions other = options;
  other.metadata += "tick_hz = 500\n";
  EXPECT_FALSE(writer.open(path, shape_, other, &error));
  EXPECT_NE(error.find("another run"), std::string::npos) << error;
  EXPECT_FALSE(writer.open(path, shape_, {}, &error));  // a plain log is not the recording either

  std::vector<uint8_t> bytes = read_bytes(path);
  bytes[hal::output::kLogHeaderBytes + 3] ^= 0x20;  // inside the metadata
  write_bytes(path, bytes.data(), bytes.size());
  const ReadBack damaged = read_log(path);
  EXPECT_FALSE(damaged.opened);
  EXPECT_NE(damaged.error.find("metadata checksum"), std::string::npos) << damaged.error;
}

// A log without metadata is still version 1, byte for byte as before.
TEST_F(FrameLogTest, WithoutMetadataTheHeaderIsVersionOne) {
  const std::string path = dir_.file("v1.log");
  write_frames(path, 0, 1);
  const std::vector<uint8_t> bytes = read_bytes(path);
  EXPECT_EQ(bytes[8], 1);
  EXPECT_EQ(bytes[28] | bytes[29] | bytes[30] | bytes[31], 0);
}

TEST_F(FrameLogTest, CutsATornTailBeforeAppending) {
  const std::string path = dir_.file("a.log");
  const std::vector<uint64_t> ends = write_frames(path, 0, 4);
  // A power cut in the middle of the fourth record.
  ASSERT_EQ(::truncate(path.c_str(), static_cast<off_t>(ends[2] + 20)), 0);
  FrameLogWriter writer;
  std::string error;
  ASSERT_TRUE(writer.open(path, shape_, {}, &error)) << error;
  EXPECT_EQ(writer.stats().tail_bytes_cut, 20u);
  EXPECT_TRUE(writer.write(poses_[3]->frame()));
  EXPECT_TRUE(writer.write(poses_[4]->frame()));
  writer.close();
  const ReadBack r = read_log(path);
  expect_frames(r.poses, kFrames);
  EXPECT_EQ(r.stop, LogStop::kEnd);
}

TEST_F(FrameLogTest, RefusesToAppendBehindDamageLargerThanOneRecord) {
  const std::string path = dir_.file("a.log");
  const std::vector<uint64_t> ends = write_frames(path, 0, kFrames);
  std::vector<uint8_t> bytes = read_bytes(path);
  bytes[ends[0] + 30] ^= 0x40;  // inside the second record: three intact records follow
  write_bytes(path, bytes.data(), bytes.size());
  FrameLogWriter writer;
  std::string error;
  EXPECT_FALSE(writer.open(path, shape_, {}, &error));
  EXPECT_NE(error.find("refusing"), std::string::npos) << error;
  EXPECT_EQ(read_bytes(path), bytes);  // nothing cut
}

TEST_F(FrameLogTest, OneWriterAtATime) {
  const std::string path = dir_.file("a.log");
  FrameLogWriter first, second;
  std::string error;
  ASSERT_TRUE(first.open(path, shape_, {}, &error)) << error;
  EXPECT_FALSE(second.open(path, shape_, {}, &error));
  EXPECT_NE(error.find("another writer"), std::string::npos) << error;
  first.close();
  EXPECT_TRUE(second.open(path, shape_, {}, &error)) << error;
}

TEST_F(FrameLogTest, RejectsAFrameOfAnotherShape) {
  FrameLogWriter writer;
  std::string error;
  ASSERT_TRUE(writer.open(dir_.file("a.log"), shape_, {}, &error)) << error;
  TestPose other(kVertices + 1, kInputs, true);
  EXPECT_FALSE(writer.write(other.frame()));
  EXPECT_EQ(writer.stats().frames_rejected, 1u);
  EXPECT_EQ(writer.file_bytes(), hal::output::kLogHeaderBytes);
}

TEST_F(FrameLogTest, SyncsEveryNFramesAndOnClose) {
  FrameLogOptions options;
  options.sync_every_frames = 2;
  FrameLogWriter writer;
  std::string error;
  ASSERT_TRUE(writer.open(dir_.file("a.log"), shape_, options, &error)) << error;
  for (uint64_t t = 0; t < kFrames; ++t) writer.write(poses_[t]->frame());
  EXPECT_EQ(writer.stats().syncs, 2u);
  writer.flush();
  EXPECT_EQ(writer.stats().syncs, 3u);
  EXPECT_EQ(writer.stats().sync_errors, 0u);
  EXPECT_NE(writer.status_line().find("5 written"), std::string::npos) << writer.status_line();
}

TEST_F(FrameLogTest, WritePathDoesNotAllocate) {
  FrameLogOptions options;
  options.sync_every_frames = 50;
  FrameLogWriter writer;
  std::string error;
  ASSERT_TRUE(writer.open(dir_.file("a.log"), shape_, options, &error)) << error;
  TestPose pose(kVertices, kInputs, true);
  AllocationCounter counter;
  for (uint64_t t = 0; t < 200; ++t) {
    pose.set_tick(t);
    writer.write(pose.frame());
  }
  writer.flush();
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_EQ(writer.stats().frames_written, 200u);
}

}  // namespace
}  // namespace sinew::test
