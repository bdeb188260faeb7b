#include <linux/can.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "candump_format.hpp"

namespace sinew::hal::can {

namespace {

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

bool is_space(char c) { return c == ' ' || c == '\t'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && (is_space(s.front()) || s.front() == '\r' || s.front() == '\n')) s.remove_prefix(1);
  while (!s.empty() && (is_space(s.back()) || s.back() == '\r' || s.back() == '\n')) s.remove_suffix(1);
  return s;
}

std::string_view next_token(std::string_view& s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  size_t n = 0;
  while (n < s.size() && !is_space(s[n])) ++n;
  std::string_view token = s.substr(0, n);
  s.remove_prefix(n);
  return token;
}

LineStatus fail(const char** error, const char* message) {
  if (error != nullptr) *error = message;
  return LineStatus::kError;
}

// "(seconds.fraction)" → nanoseconds. The fraction is decimal, 1..9 digits.
bool parse_timestamp(std::string_view t, uint64_t& ns) {
  if (t.size() < 4 || t.front() != '(' || t.back() != ')') return false;
  t = t.substr(1, t.size() - 2);
  const size_t dot = t.find('.');
  if (dot == std::string_view::npos || dot == 0 || dot > 10 || t.size() - dot - 1 < 1 || t.size() - dot - 1 > 9)
    return false;
  uint64_t sec = 0;
  for (char c : t.substr(0, dot)) {
    if (c < '0' || c > '9') return false;
    sec = sec * 10 + static_cast<uint64_t>(c - '0');
  }
  uint64_t frac = 0;
  size_t digits = 0;
  for (char c : t.substr(dot + 1)) {
    if (c < '0' || c > '9') return false;
    frac = frac * 10 + static_cast<uint64_t>(c - '0');
    ++digits;
  }
  for (; digits < 9; ++digits) frac *= 10;
  ns = sec * 1'000'000'000u + frac;  // sec < 10^10: no overflow
  return true;
}

// Hex byte pairs, optionally separated by '.', into data; stops at '_' or end.
bool parse_data(std::string_view& s, CanFrame& f, size_t max_len, const char** error) {
  size_t len = 0;
  while (!s.empty() && s.front() != '_') {
    if (s.front() == '.') {
      s.remove_prefix(1);
      continue;
    }
    if (s.size() < 2 || hex_value(s[0]) < 0 || hex_value(s[1]) < 0) {
      fail(error, "data must be pairs of hex digits");
      return false;
    }
    if (len == max_len) {
      fail(error,
           max_len == kClassicMaxLen ? "more than 8 data bytes in a classic CAN frame" : "more than 64 data bytes");
      return false;
    }
    f.data[len++] = static_cast<uint8_t>(hex_value(s[0]) * 16 + hex_value(s[1]));
    s.remove_prefix(2);
  }
  f.len = static_cast<uint8_t>(len);
  return true;
}

// "_X": raw DLC 9..15 for an 8-byte classic frame.
bool parse_len8_dlc(std::string_view& s, CanFrame& f, const char** error) {
  if (s.empty()) return true;
  if (s.size() != 2 || s[0] != '_' || hex_value(s[1]) < 9 || f.len != kClassicMaxLen) {
    fail(error, "'_' must be followed by one raw DLC digit 9..F, after exactly 8 bytes");
    return false;
  }
  f.len8_dlc = static_cast<uint8_t>(hex_value(s[1]));
  s.remove_prefix(2);
  return true;
}

LineStatus parse_frame(std::string_view s, CanFrame& f, const char** error) {
  const size_t hash = s.find('#');
  if (hash == std::string_view::npos) return fail(error, "frame has no '#'");
  if (s.find(':') != std::string_view::npos) return fail(error, "CAN XL frames are not supported");
  const std::string_view id_text = s.substr(0, hash);
  uint32_t id = 0;
  for (char c : id_text) {
    if (hex_value(c) < 0) return fail(error, "identifier is not hexadecimal");
    id = id * 16 + static_cast<uint32_t>(hex_value(c));
  }
  if (id_text.size() == 3) {
    if (id > CAN_SFF_MASK) return fail(error, "11-bit identifier above 7FF");
    f.id = id;
  } else if (id_text.size() == 8) {
    if ((id & (CAN_EFF_FLAG | CAN_RTR_FLAG)) != 0) return fail(error, "29-bit identifier above 1FFFFFFF");
    if ((id & CAN_ERR_FLAG) != 0) {
      f.kind = FrameKind::kError;
      f.id = id & CAN_ERR_MASK;
    } else {
      f.extended = true;
      f.id = id;
    }
  } else {
    return fail(error, "identifier must have 3 or 8 hex digits");
  }
  s.remove_prefix(hash + 1);

  if (!s.empty() && s.front() == '#') {  // CAN FD: "##<flags nibble><data>"
    if (f.kind == FrameKind::kError) return fail(error, "an error frame cannot be CAN FD");
    if (s.size() < 2 || hex_value(s[1]) < 0) return fail(error, "CAN FD frame needs a flags nibble after '##'");
    f.fd = true;
    f.fd_flags = static_cast<uint8_t>(hex_value(s[1]));
    s.remove_prefix(2);
    if (!parse_data(s, f, kFdMaxLen, error)) return LineStatus::kError;
    if (!s.empty()) return fail(error, "unexpected characters after CAN FD data");
    if (!is_valid_fd_len(f.len))
      return fail(error, "CAN FD length is not one a DLC can express (0..8,12,16,20,24,32,48,64)");
    return LineStatus::kFrame;
  }
  if (!s.empty() && (s.front() == 'R' || s.front() == 'r')) {
    if (f.kind == FrameKind::kError) return fail(error, "an error frame cannot be a remote frame");
    f.kind = FrameKind::kRemote;
    s.remove_prefix(1);
    if (!s.empty() && s.front() != '_') {
      const int len = hex_value(s.front());
      if (len < 0 || len > 8) return fail(error, "remote frame length must be one digit 0..8");
      f.len = static_cast<uint8_t>(len);
      s.remove_prefix(1);
    }
    if (!parse_len8_dlc(s, f, error)) return LineStatus::kError;
    return s.empty() ? LineStatus::kFrame : fail(error, "unexpected characters after remote frame");
  }
  if (!parse_data(s, f, kClassicMaxLen, error)) return LineStatus::kError;
  if (!parse_len8_dlc(s, f, error)) return LineStatus::kError;
  return LineStatus::kFrame;
}

}  // namespace

LineStatus parse_candump_line(std::string_view line, CandumpLine& out, const char** error) {
  std::string_view s = trim(line);
  if (s.empty() || s.front() == '#') return LineStatus::kSkipped;
  out = CandumpLine{};
  if (s.front() != '(') return fail(error, "line does not start with a '(' timestamp");
  if (!parse_timestamp(next_token(s), out.frame.timestamp_ns)) {
    return fail(error, "timestamp must be (seconds.fraction) with 1..10 and 1..9 digits");
  }
  out.interface = next_token(s);
  if (out.interface.empty()) return fail(error, "missing interface name");
  const std::string_view frame_text = next_token(s);
  if (frame_text.empty()) return fail(error, "missing frame");
  const LineStatus status = parse_frame(frame_text, out.frame, error);
  if (status != LineStatus::kFrame) return status;
  const std::string_view rest = next_token(s);
  if (!rest.empty()) {
    if (rest.size() != 1 || (rest[0] != 'R' && rest[0] != 'T') || !next_token(s).empty()) {
      return fail(error, "unexpected text after the frame (only R or T may follow)");
    }
    out.direction = rest[0];
  }
  return LineStatus::kFrame;
}

CandumpLog parse_candump_log(std::string_view text) {
  CandumpLog log;
  size_t line_no = 0;
  while (!text.empty()) {
    const size_t nl = text.find('\n');
    const std::string_view line = text.substr(0, nl);
    text.remove_prefix(nl == std::string_view::npos ? text.size() : nl + 1);
    ++line_no;
    CandumpLine parsed;
    const char* message = nullptr;
    switch (parse_candump_line(line, parsed, &message)) {
      case LineStatus::kFrame:
        log.frames.push_back({parsed.frame, std::string(parsed.interface), parsed.direction, line_no});
        break;
      case LineStatus::kSkipped:
        break;
      case LineStatus::kError:
        log.errors.push_back({line_no, message != nullptr ? message : "malformed line"});
        break;
    }
  }
  log.lines = line_no;
  return log;
}

bool read_candump_file(const std::string& path, CandumpLog& out, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (error != nullptr) *error = "cannot open " + path;
    return false;
  }
  std::ostringstream text;
  text << in.rdbuf();
  out = parse_candump_log(text.str());
  return true;
}

}  // namespace sinew::hal::can
