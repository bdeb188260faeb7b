// Fixed-capacity message builder: error text without heap or stdio.
#pragma once

#include <cstddef>
#include <cstdint>

namespace sinew::rig {

class MessageBuilder {
 public:
  MessageBuilder(char* buffer, size_t capacity) : buf_(buffer), cap_(capacity) {
    if (cap_ > 0) buf_[0] = '\0';
  }
  MessageBuilder& text(const char* s) {
    while (s != nullptr && *s != '\0') put(*s++);
    return *this;
  }
  MessageBuilder& number(int64_t v) {
    const uint64_t mag = v < 0 ? uint64_t{0} - static_cast<uint64_t>(v) : static_cast<uint64_t>(v);
    if (v < 0) put('-');
    return unsigned_number(mag);
  }
  MessageBuilder& unsigned_number(uint64_t v) {
    char digits[20];
    int n = 0;
    do {
      digits[n++] = static_cast<char>('0' + v % 10);
      v /= 10;
    } while (v != 0);
    while (n > 0) put(digits[--n]);
    return *this;
  }

 private:
  void put(char c) {
    if (len_ + 1 < cap_) {
      buf_[len_++] = c;
      buf_[len_] = '\0';
    }
  }
  char* buf_;
  size_t cap_;
  size_t len_ = 0;
};

}  // namespace sinew::rig
