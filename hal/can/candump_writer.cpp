#include <linux/can.h>

#include <cstdio>

#include "candump_format.hpp"

namespace sinew::hal::can {

namespace {

constexpr char kHex[] = "0123456789ABCDEF";

class LineBuilder {
 public:
  explicit LineBuilder(std::span<char> out) : out_(out) {}
  void put(char c) {
    if (n_ < out_.size()) out_[n_] = c;
    ++n_;
  }
  void put(std::string_view s) {
    for (char c : s) put(c);
  }
  void hex(uint64_t v, int digits) {
    for (int i = digits - 1; i >= 0; --i) put(kHex[(v >> (4 * i)) & 0xFu]);
  }
  void dec(uint64_t v, int min_digits) {
    char buf[20];
    int n = 0;
    do {
      buf[n++] = static_cast<char>('0' + v % 10);
      v /= 10;
    } while (v != 0);
    for (int i = n; i < min_digits; ++i) put('0');
    while (n > 0) put(buf[--n]);
  }
  size_t finish() const { return n_ <= out_.size() ? n_ : 0; }

 private:
  std::span<char> out_;
  size_t n_ = 0;
};

}  // namespace

size_t format_candump_line(const CanFrame& frame, std::string_view interface, std::span<char> out) {
  if (!is_well_formed(frame) || interface.empty()) return 0;
  for (char c : interface) {
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') return 0;
  }
  LineBuilder b(out);
  // candump: "(%010lu.%06lu) %s " from the kernel's struct timeval.
  b.put('(');
  b.dec(frame.timestamp_ns / 1'000'000'000u, 10);
  b.put('.');
  b.dec((frame.timestamp_ns % 1'000'000'000u) / 1000u, 6);
  b.put(") ");
  b.put(interface);
  b.put(' ');
  if (frame.kind == FrameKind::kError) {
    b.hex(frame.id | CAN_ERR_FLAG, 8);
  } else {
    b.hex(frame.id, frame.extended ? 8 : 3);
  }
  b.put('#');
  if (frame.fd) {
    b.put('#');
    b.hex(frame.fd_flags & 0xFu, 1);
  } else if (frame.kind == FrameKind::kRemote) {
    b.put('R');
    if (frame.len > 0) b.hex(frame.len, 1);
  }
  if (frame.kind != FrameKind::kRemote) {
    for (size_t i = 0; i < frame.len; ++i) b.hex(frame.data[i], 2);
  }
  if (frame.len8_dlc != 0) {
    b.put('_');
    b.hex(frame.len8_dlc, 1);
  }
  b.put('\n');
  return b.finish();
}

}  // namespace sinew::hal::can
