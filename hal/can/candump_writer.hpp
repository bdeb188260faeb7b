// Records frames as a candump log file (the format of candump_format.hpp),
// for logs the firmware keeps. The stdio buffer is the writer's own, so
// writing a frame never allocates.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "candump_format.hpp"

namespace sinew::hal::can {

class CandumpWriter {
 public:
  CandumpWriter() = default;
  ~CandumpWriter();
  CandumpWriter(const CandumpWriter&) = delete;
  CandumpWriter& operator=(const CandumpWriter&) = delete;

  // Creates the file anew, empty, replacing a regular file at the path; a
  // symbolic link there is refused, never followed, and so is a
  // world-writable directory without the sticky bit (safe_create.hpp).
  // Configuration time.
  bool open(const std::string& path, std::string* error, size_t buffer_bytes = 64 * 1024);
  // One line; false if the frame cannot be formatted or the write failed (counted).
  bool write(const CanFrame& frame, std::string_view interface);
  bool flush();
  void close();

  uint64_t lines_written() const { return lines_; }
  uint64_t failures() const { return failures_; }

 private:
  std::FILE* file_ = nullptr;
  std::vector<char> buffer_;
  uint64_t lines_ = 0;
  uint64_t failures_ = 0;
};

}  // namespace sinew::hal::can
