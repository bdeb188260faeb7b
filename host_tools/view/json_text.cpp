#include "json_text.hpp"

#include <cinttypes>
#include <cmath>
#include <cstdio>

namespace sinew::view {

void JsonText::separate() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (!first_.empty()) {
    if (!first_.back()) text_ += ',';
    first_.back() = false;
  }
}

JsonText& JsonText::open(char c) {
  separate();
  text_ += c;
  first_.push_back(true);
  return *this;
}

JsonText& JsonText::close(char c) {
  text_ += c;
  first_.pop_back();
  return *this;
}

JsonText& JsonText::key(const char* k) {
  string(k);
  text_ += ':';
  after_key_ = true;
  return *this;
}

JsonText& JsonText::string(const std::string& s) {
  separate();
  text_ += '"';
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      text_ += '\\';
      text_ += ch;
    } else if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      text_ += buf;
    } else {
      text_ += ch;
    }
  }
  text_ += '"';
  return *this;
}

JsonText& JsonText::number(double v) {
  separate();
  if (!std::isfinite(v)) {
    text_ += "null";
    return *this;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  text_ += buf;
  return *this;
}

JsonText& JsonText::number(int64_t v) {
  separate();
  text_ += std::to_string(v);
  return *this;
}

JsonText& JsonText::number(uint64_t v) {
  separate();
  text_ += std::to_string(v);
  return *this;
}

JsonText& JsonText::boolean(bool b) {
  separate();
  text_ += b ? "true" : "false";
  return *this;
}

JsonText& JsonText::null() {
  separate();
  text_ += "null";
  return *this;
}

}  // namespace sinew::view
