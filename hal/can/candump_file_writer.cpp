#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "candump_writer.hpp"
#include "hal/common/safe_create.hpp"

namespace sinew::hal::can {

CandumpWriter::~CandumpWriter() { close(); }

bool CandumpWriter::open(const std::string& path, std::string* error, size_t buffer_bytes) {
  close();
  std::string why;
  // A new file renamed into place: never written through a link planted at the path (safe_create.hpp).
  const int fd = create_replacing(path, "candump record", 0666, &why);
  if (fd >= 0 && (file_ = ::fdopen(fd, "wb")) == nullptr) {
    why = "candump record " + path + ": " + std::strerror(errno);
    ::close(fd);
  }
  if (file_ == nullptr) {
    if (error != nullptr) *error = why;
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
