// can-utils' compact log format, as written by `candump -l` / `candump -L`
// and read by canplayer and log2asc:
//
//   (1436509052.249713) vcan0 123#DEADBEEF          classic, 11-bit identifier
//   (1436509052.249713) vcan0 1F334455#1122         classic, 29-bit identifier (8 hex digits)
//   (1436509052.249713) vcan0 123#R  / 123#R3       remote frame (requested length)
//   (1436509052.249713) vcan0 123#                  no data
//   (1436509052.249713) vcan0 123#1122334455667788_E  8 bytes sent with raw DLC 0xE
//   (1436509052.249713) vcan0 123##1DEADBEEF        CAN FD, flags nibble 1 (BRS)
//   (1436509052.249713) vcan0 20000040#0000000000000000  error frame (CAN_ERR_FLAG set)
//   (1436509052.249713) vcan0 123#DEADBEEF R        trailing R/T: direction (candump -x)
//
// Data bytes may be separated by '.'. canplayer skips lines not starting
// with '('; here blank lines and lines starting with '#' are skipped and any
// other line is an error with its line number, so damage is reported.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "can_frame.hpp"

namespace sinew::hal::can {

enum class LineStatus : uint8_t { kFrame, kSkipped, kError };

struct CandumpLine {
  CanFrame frame;              // timestamp_ns: the log's timestamp (seconds as written, usually Unix time)
  std::string_view interface;  // points into the parsed line
  char direction = 0;          // 'R' or 'T' if present, else 0
};

// Parses one line (without or with its '\r'/'\n'). On kError, `error` (if
// given) points to a static message. Never allocates.
LineStatus parse_candump_line(std::string_view line, CandumpLine& out, const char** error = nullptr);

struct LoggedFrame {
  CanFrame frame;
  std::string interface;
  char direction = 0;
  size_t line = 0;  // 1-based line number in the log
};

struct CandumpError {
  size_t line = 0;  // 1-based
  std::string message;
};

struct CandumpLog {
  std::vector<LoggedFrame> frames;
  std::vector<CandumpError> errors;
  size_t lines = 0;
};

// Whole logs (offline tools, tests). LF or CRLF line endings.
CandumpLog parse_candump_log(std::string_view text);
bool read_candump_file(const std::string& path, CandumpLog& out, std::string* error);

// --- writing ---

inline constexpr size_t kCandumpLineMax = 256;

// Formats one frame as a candump log line ending in '\n' into `out`.
// Timestamps are written with microsecond resolution, as candump does.
// Returns the length, or 0 if the frame is not well formed, the interface
// name is empty or has spaces, or `out` is too small. Never allocates.
size_t format_candump_line(const CanFrame& frame, std::string_view interface, std::span<char> out);

}  // namespace sinew::hal::can
