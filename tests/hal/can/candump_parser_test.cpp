// candump log lines: every frame kind can-utils writes, a real capture, and
// bad lines reported with their line numbers (never a crash).
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "hal/can/candump_format.hpp"

namespace sinew::hal::can {
namespace {

CandumpLine parse_ok(std::string_view text) {
  CandumpLine line;
  const char* error = nullptr;
  EXPECT_EQ(parse_candump_line(text, line, &error), LineStatus::kFrame) << text << ": " << (error ? error : "");
  return line;
}

const char* parse_error(std::string_view text) {
  CandumpLine line;
  const char* error = nullptr;
  EXPECT_EQ(parse_candump_line(text, line, &error), LineStatus::kError) << text;
  return error != nullptr ? error : "";
}

TEST(CandumpParser, ClassicStandardFrame) {
  const CandumpLine l = parse_ok("(1436509052.249713) vcan0 123#DEADBEEF");
  EXPECT_EQ(l.frame.timestamp_ns, 1436509052249713000u);
  EXPECT_EQ(l.interface, "vcan0");
  EXPECT_EQ(l.frame.kind, FrameKind::kData);
  EXPECT_FALSE(l.frame.extended);
  EXPECT_FALSE(l.frame.fd);
  EXPECT_EQ(l.frame.id, 0x123u);
  ASSERT_EQ(l.frame.len, 4);
  EXPECT_EQ(l.frame.data[0], 0xDE);
  EXPECT_EQ(l.frame.data[3], 0xEF);
  EXPECT_EQ(l.direction, 0);
}

TEST(CandumpParser, ExtendedIdentifierHasEightDigits) {
  const CandumpLine l = parse_ok("(0000000001.000000) can1 1F334455#1122");
  EXPECT_TRUE(l.frame.extended);
  EXPECT_EQ(l.frame.id, 0x1F334455u);
  EXPECT_EQ(l.frame.len, 2);
  // Eight digits with a small value is still an extended frame.
  EXPECT_TRUE(parse_ok("(1.0) can0 00000123#").frame.extended);
}

TEST(CandumpParser, EmptyDataAndDotSeparators) {
  EXPECT_EQ(parse_ok("(1.5) can0 123#").frame.len, 0);
  const CandumpLine l = parse_ok("(1.5) can0 123#11.2233.44556677.88");
  ASSERT_EQ(l.frame.len, 8);
  EXPECT_EQ(l.frame.data[7], 0x88);
  EXPECT_EQ(l.frame.timestamp_ns, 1'500'000'000u);  // the fraction is decimal
}

TEST(CandumpParser, RemoteFrames) {
  CandumpLine l = parse_ok("(2.000000) vcan0 123#R");
  EXPECT_EQ(l.frame.kind, FrameKind::kRemote);
  EXPECT_EQ(l.frame.len, 0);
  l = parse_ok("(2.000000) vcan0 12345678#R7");
  EXPECT_EQ(l.frame.kind, FrameKind::kRemote);
  EXPECT_TRUE(l.frame.extended);
  EXPECT_EQ(l.frame.len, 7);
  EXPECT_EQ(parse_ok("(2.0) vcan0 7A1#r").frame.kind, FrameKind::kRemote);
}

TEST(CandumpParser, CanFdWithFlagsNibble) {
  const CandumpLine l = parse_ok("(3.000000) can0 123##1DEADBEEF");
  EXPECT_TRUE(l.frame.fd);
  EXPECT_EQ(l.frame.fd_flags, kFdBitRateSwitch);
  EXPECT_EQ(l.frame.len, 4);
  EXPECT_EQ(parse_ok("(3.0) can0 123##3").frame.len, 0);
  std::string sixty_four = "(3.0) can0 1FFFFFFF##5";
  for (int i = 0; i < 64; ++i) sixty_four += "A5";
  const CandumpLine big = parse_ok(sixty_four);
  EXPECT_EQ(big.frame.len, 64);
  EXPECT_TRUE(big.frame.extended);
  EXPECT_EQ(big.frame.fd_flags, kFdBitRateSwitch | kFdFrameFormat);
}

TEST(CandumpParser, ErrorFrames) {
  const CandumpLine l = parse_ok("(4.000000) can0 20000040#0000000000000000");
  EXPECT_EQ(l.frame.kind, FrameKind::kError);
  EXPECT_EQ(l.frame.id, 0x40u);  // CAN_ERR_BUSOFF
  EXPECT_FALSE(l.frame.extended);
  EXPECT_EQ(l.frame.len, 8);
}

TEST(CandumpParser, RawDlcAfterEightBytes) {
  const CandumpLine l = parse_ok("(5.0) can0 123#1122334455667788_E");
  EXPECT_EQ(l.frame.len, 8);
  EXPECT_EQ(l.frame.len8_dlc, 0xE);
  EXPECT_STRNE(parse_error("(5.0) can0 123#11_E"), "");
  EXPECT_STRNE(parse_error("(5.0) can0 123#1122334455667788_3"), "");
}

TEST(CandumpParser, DirectionFromCandumpX) {
  EXPECT_EQ(parse_ok("(6.0) can0 123#00 R").direction, 'R');
  EXPECT_EQ(parse_ok("(6.0) can0 123#00 T").direction, 'T');
  EXPECT_STRNE(parse_error("(6.0) can0 123#00 X"), "");
  EXPECT_STRNE(parse_error("(6.0) can0 123#00 R extra"), "");
}

TEST(CandumpParser, PaddedInterfaceNamesCrlfAndTabs) {
  const CandumpLine l = parse_ok("(0000000007.000001)   vcan0 123#01\r\n");
  EXPECT_EQ(l.interface, "vcan0");
  EXPECT_EQ(l.frame.timestamp_ns, 7'000'001'000u);
  EXPECT_EQ(parse_ok("(7.0)\tcan0\t123#01").frame.len, 1);
}

TEST(CandumpParser, BlankAndCommentLinesAreSkipped) {
  CandumpLine l;
  EXPECT_EQ(parse_candump_line("", l), LineStatus::kSkipped);
  EXPECT_EQ(parse_candump_line("   \r", l), LineStatus::kSkipped);
  EXPECT_EQ(parse_candump_line("# recorded on the bench", l), LineStatus::kSkipped);
  EXPECT_EQ(parse_candump_line("  # indented comment", l), LineStatus::kSkipped);
}

TEST(CandumpParser, BadLinesSayWhy) {
  EXPECT_STREQ(parse_error("vcan0 123#00"), "line does not start with a '(' timestamp");
  EXPECT_STRNE(parse_error("(abc) vcan0 123#00"), "");
  EXPECT_STRNE(parse_error("(1436509052) vcan0 123#00"), "");             // no fraction
  EXPECT_STRNE(parse_error("(1.0123456789) vcan0 123#00"), "");           // 10 fraction digits
  EXPECT_STRNE(parse_error("(1.0) vcan0"), "");                           // no frame
  EXPECT_STRNE(parse_error("(1.0)"), "");                                 // no interface
  EXPECT_STRNE(parse_error("(1.0) vcan0 123"), "");                       // no '#'
  EXPECT_STRNE(parse_error("(1.0) vcan0 1234#00"), "");                   // 4 digits
  EXPECT_STRNE(parse_error("(1.0) vcan0 800#00"), "");                    // > 7FF
  EXPECT_STRNE(parse_error("(1.0) vcan0 40000000#00"), "");               // > 29 bits
  EXPECT_STRNE(parse_error("(1.0) vcan0 12G#00"), "");                    // not hex
  EXPECT_STRNE(parse_error("(1.0) vcan0 123#0"), "");                     // odd digit count
  EXPECT_STRNE(parse_error("(1.0) vcan0 123#001122334455667788"), "");    // 9 bytes classic
  EXPECT_STRNE(parse_error("(1.0) vcan0 123#R9"), "");                    // remote length > 8
  EXPECT_STRNE(parse_error("(1.0) vcan0 123##"), "");                     // FD without flags
  EXPECT_STRNE(parse_error("(1.0) vcan0 123##0001122334455667788"), "");  // FD length 9
  EXPECT_STRNE(parse_error("(1.0) vcan0 20000004#R"), "");                // remote error frame
  EXPECT_STREQ(parse_error("(1.0) vcan0 45123#81:00:12345678#11"), "CAN XL frames are not supported");
}

TEST(CandumpParser, LogReportsEachBadLineWithItsNumber) {
  const CandumpLog log = parse_candump_log(
      "# header comment\n"
      "(1.000000) can0 123#01\n"
      "\n"
      "(1.000100) can0 123#0\n"
      "garbage\r\n"
      "(1.000200) can0 1FFFFFFF#0102\r\n"
      "(1.000300) can0 123#R");  // last line without a newline
  ASSERT_EQ(log.frames.size(), 3u);
  EXPECT_EQ(log.frames[0].line, 2u);
  EXPECT_EQ(log.frames[1].line, 6u);
  EXPECT_EQ(log.frames[1].interface, "can0");
  EXPECT_EQ(log.frames[2].frame.kind, FrameKind::kRemote);
  ASSERT_EQ(log.errors.size(), 2u);
  EXPECT_EQ(log.errors[0].line, 4u);
  EXPECT_EQ(log.errors[1].line, 5u);
  EXPECT_EQ(log.lines, 7u);
}

TEST(CandumpParser, ArbitraryBytesNeverCrash) {
  uint64_t state = 0xD1B54A32D192ED03u;
  auto next = [&] {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  std::string alphabet = "()#.R_:rT 0123456789ABCDEFabcdefgG\t\r\n";
  alphabet.push_back('\0');
  alphabet.push_back(static_cast<char>(0xFF));
  std::string text;
  for (int i = 0; i < 20000; ++i) {
    std::string line = (next() % 2 == 0) ? "(1.0) can0 " : "";
    const size_t n = next() % 40;
    for (size_t k = 0; k < n; ++k) line += alphabet[next() % alphabet.size()];
    text += line + "\n";
  }
  const CandumpLog log = parse_candump_log(text);
  EXPECT_GT(log.errors.size(), 0u);
  for (const LoggedFrame& f : log.frames) EXPECT_TRUE(is_well_formed(f.frame));
}

TEST(CandumpParser, RealCaptureFromCanboat) {
  CandumpLog log;
  std::string error;
  ASSERT_TRUE(read_candump_file(SINEW_TEST_DATA_DIR "/canboat_actisense-522.candump.log", log, &error)) << error;
  EXPECT_TRUE(log.errors.empty()) << "line " << log.errors[0].line << ": " << log.errors[0].message;
  ASSERT_EQ(log.frames.size(), 106u);
  std::set<uint32_t> ids;
  uint64_t previous = 0;
  for (const LoggedFrame& f : log.frames) {
    EXPECT_TRUE(f.frame.extended);
    EXPECT_EQ(f.frame.kind, FrameKind::kData);
    EXPECT_EQ(f.frame.len, 8);
    EXPECT_EQ(f.interface, "can0");
    EXPECT_GE(f.frame.timestamp_ns, previous);
    previous = f.frame.timestamp_ns;
    ids.insert(f.frame.id);
  }
  EXPECT_EQ(ids.size(), 14u);
  const CanFrame& first = log.frames.front().frame;
  EXPECT_EQ(first.id, 0x11FC1063u);
  EXPECT_EQ(first.timestamp_ns, 1745600961335462000u);
  const uint8_t expected[8] = {0x00, 0x3D, 0xFF, 0xFF, 0x02, 0x00, 0x01, 0x00};
  for (size_t i = 0; i < 8; ++i) EXPECT_EQ(first.data[i], expected[i]) << i;
  EXPECT_EQ(log.frames.back().frame.timestamp_ns, 1745600961338397000u);
}

}  // namespace
}  // namespace sinew::hal::can
