#include <cerrno>
#include <cstring>

#include "candump_writer.hpp"

namespace sinew::hal::can {

CandumpWriter::~CandumpWriter() { close(); }

bool CandumpWriter::open(const std::string& path, std::string* error, size_t buffer_bytes) {
  close();
  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) {
    if (error != nullptr) *error = "cannot create " + path + ": " + std::strerror(errno);
    return false;
  }
  buffer_.assign(buffer_bytes < kCandumpLineMax ? kCandumpLineMax : buffer_bytes, '\0');
  std::setvbuf(file_, buffer_.data(), _IOFBF, buffer_.size());
  return true;
}

bool CandumpWriter::write(const CanFrame& frame, std::string_view interface) {
  char line[kCandumpLineMax];
  const size_t n = format_candump_line(frame, interface, line);
  if (file_ == nullptr || n == 0 || std::fwrite(line, 1, n, file_) != n) {
    ++failures_;
    return false;
  }
  ++lines_;
  return true;
}

bool CandumpWriter::flush() { return file_ != nullptr && std::fflush(file_) == 0; }

void CandumpWriter::close() {
  if (file_ != nullptr) std::fclose(file_);
  file_ = nullptr;
}

}  // namespace sinew::hal::can
