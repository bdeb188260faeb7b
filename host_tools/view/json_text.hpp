// A minimal JSON writer for the viewer's messages (objects, arrays, numbers,
// strings): commas are placed by the writer, strings escaped.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace sinew::view {

class JsonText {
 public:
  JsonText& open_object() { return open('{'); }
  JsonText& close_object() { return close('}'); }
  JsonText& open_array() { return open('['); }
  JsonText& close_array() { return close(']'); }
  JsonText& key(const char* k);
  JsonText& string(const std::string& s);
  JsonText& number(double v);
  JsonText& number(int64_t v);
  JsonText& number(uint64_t v);
  JsonText& number(int32_t v) { return number(static_cast<int64_t>(v)); }
  JsonText& number(uint32_t v) { return number(static_cast<uint64_t>(v)); }
  JsonText& boolean(bool b);
  JsonText& null();
  std::string take() { return std::move(text_); }

 private:
  JsonText& open(char c);
  JsonText& close(char c);
  void separate();
  std::string text_;
  std::vector<bool> first_;  // per open container: nothing written in it yet
  bool after_key_ = false;
};

}  // namespace sinew::view
