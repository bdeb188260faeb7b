// The writer produces candump's exact text, and what it writes parses back.
#include "hal/can/candump_writer.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "hal/can/candump_format.hpp"
#include "tests/support/alloc_guard.hpp"

namespace sinew::hal::can {
namespace {

std::string line_of(const CanFrame& f, std::string_view iface = "can0") {
  char buf[kCandumpLineMax];
  const size_t n = format_candump_line(f, iface, buf);
  return std::string(buf, n);
}

CanFrame data_frame(uint32_t id, bool extended, std::initializer_list<int> bytes, uint64_t t_ns) {
  CanFrame f;
  f.id = id;
  f.extended = extended;
  f.timestamp_ns = t_ns;
  for (int b : bytes) f.data[f.len++] = static_cast<uint8_t>(b);
  return f;
}

TEST(CandumpWriter, ExactCandumpText) {
  EXPECT_EQ(line_of(data_frame(0x123, false, {0xDE, 0xAD, 0xBE, 0xEF}, 1436509052249713000u), "vcan0"),
            "(1436509052.249713) vcan0 123#DEADBEEF\n");
  EXPECT_EQ(line_of(data_frame(0x11FC1063, true, {0, 0x3D}, 7'000'001'999u)),
            "(0000000007.000001) can0 11FC1063#003D\n");
  EXPECT_EQ(line_of(data_frame(0x7FF, false, {}, 0)), "(0000000000.000000) can0 7FF#\n");
}

TEST(CandumpWriter, RemoteErrorFdAndRawDlc) {
  CanFrame remote = data_frame(0x123, false, {}, 0);
  remote.kind = FrameKind::kRemote;
  EXPECT_EQ(line_of(remote), "(0000000000.000000) can0 123#R\n");
  remote.len = 3;
  EXPECT_EQ(line_of(remote), "(0000000000.000000) can0 123#R3\n");

  CanFrame error = data_frame(0x40, false, {0, 0, 0, 0, 0, 0, 0, 0}, 0);
  error.kind = FrameKind::kError;
  EXPECT_EQ(line_of(error), "(0000000000.000000) can0 20000040#0000000000000000\n");

  CanFrame fd = data_frame(0x123, false, {0xDE, 0xAD, 0xBE, 0xEF}, 0);
  fd.fd = true;
  fd.fd_flags = kFdBitRateSwitch;
  EXPECT_EQ(line_of(fd), "(0000000000.000000) can0 123##1DEADBEEF\n");

  CanFrame dlc = data_frame(0x123, false, {1, 2, 3, 4, 5, 6, 7, 8}, 0);
  dlc.len8_dlc = 0xF;
  EXPECT_EQ(line_of(dlc), "(0000000000.000000) can0 123#0102030405060708_F\n");
}

TEST(CandumpWriter, RefusesWhatItCannotWrite) {
  char small[10];
  EXPECT_EQ(format_candump_line(data_frame(0x123, false, {1}, 0), "can0", small), 0u);
  char buf[kCandumpLineMax];
  EXPECT_EQ(format_candump_line(data_frame(0x800, false, {1}, 0), "can0", buf), 0u);  // not 11-bit
  EXPECT_EQ(format_candump_line(data_frame(0x123, false, {1}, 0), "", buf), 0u);
  EXPECT_EQ(format_candump_line(data_frame(0x123, false, {1}, 0), "can 0", buf), 0u);
}

TEST(CandumpWriter, EveryKindRoundTripsThroughTheParser) {
  std::string text;
  std::vector<CanFrame> frames;
  frames.push_back(data_frame(0x001, false, {}, 1'000'000'000u));
  frames.push_back(data_frame(0x1ABCDEF0, true, {1, 2, 3, 4, 5, 6, 7, 8}, 1'000'001'000u));
  CanFrame r = data_frame(0x55, false, {}, 2'000'000'000u);
  r.kind = FrameKind::kRemote;
  r.len = 8;
  r.len8_dlc = 9;
  frames.push_back(r);
  CanFrame fd = data_frame(0x180, false, {}, 3'000'000'000u);
  fd.fd = true;
  fd.fd_flags = kFdFrameFormat | kFdBitRateSwitch;
  fd.len = 64;
  for (size_t i = 0; i < 64; ++i) fd.data[i] = static_cast<uint8_t>(i * 3);
  frames.push_back(fd);
  CanFrame e = data_frame(0x04, false, {0, 0x10, 0, 0, 0, 0, 0x80, 0x20}, 4'000'000'000u);
  e.kind = FrameKind::kError;
  frames.push_back(e);
  for (const CanFrame& f : frames) text += line_of(f);

  const CandumpLog log = parse_candump_log(text);
  ASSERT_TRUE(log.errors.empty()) << log.errors[0].message;
  ASSERT_EQ(log.frames.size(), frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    const CanFrame& a = frames[i];
    const CanFrame& b = log.frames[i].frame;
    EXPECT_EQ(a.id, b.id) << i;
    EXPECT_EQ(a.kind, b.kind) << i;
    EXPECT_EQ(a.extended, b.extended) << i;
    EXPECT_EQ(a.fd, b.fd) << i;
    EXPECT_EQ(a.len, b.len) << i;
    EXPECT_EQ(a.fd_flags, b.fd_flags) << i;
    EXPECT_EQ(a.len8_dlc, b.len8_dlc) << i;
    EXPECT_EQ(a.timestamp_ns, b.timestamp_ns) << i;
    if (a.kind != FrameKind::kRemote) {
      EXPECT_EQ(a.data, b.data) << i;
    }
  }
}

TEST(CandumpWriter, RealCaptureRewritesByteForByte) {
  std::ifstream in(SINEW_TEST_DATA_DIR "/canboat_actisense-522.candump.log", std::ios::binary);
  std::stringstream original;
  original << in.rdbuf();
  const CandumpLog log = parse_candump_log(original.str());
  ASSERT_EQ(log.frames.size(), 106u);
  std::string rewritten;
  for (const LoggedFrame& f : log.frames) {
    std::string line = line_of(f.frame, f.interface);
    line.pop_back();
    line += "\r\n";  // the capture has CRLF line endings
    rewritten += line;
  }
  EXPECT_EQ(rewritten, original.str());
}

TEST(CandumpWriter, FileWriterDoesNotAllocatePerFrame) {
  char path[] = "/tmp/sinew-candump-XXXXXX";
  const int fd = mkstemp(path);
  ASSERT_GE(fd, 0);
  ::close(fd);
  CandumpWriter writer;
  std::string error;
  ASSERT_TRUE(writer.open(path, &error)) << error;
  const CanFrame f = data_frame(0x123, false, {1, 2, 3}, 5'000'000'000u);
  writer.write(f, "can0");  // first write: stdio settles its state
  {
    test::AllocationCounter counter;
    for (int i = 0; i < 1000; ++i) ASSERT_TRUE(writer.write(f, "can0"));
    EXPECT_EQ(counter.allocations(), 0u);
  }
  ASSERT_TRUE(writer.flush());
  writer.close();
  CandumpLog log;
  ASSERT_TRUE(read_candump_file(path, log, &error));
  EXPECT_EQ(log.frames.size(), 1001u);
  EXPECT_TRUE(log.errors.empty());
  EXPECT_EQ(writer.lines_written(), 1001u);
  std::remove(path);
}

}  // namespace
}  // namespace sinew::hal::can
