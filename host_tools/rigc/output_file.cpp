#include "output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "hal/common/safe_create.hpp"

namespace sinew::rigc {
namespace {

bool is_stream(mode_t mode) { return S_ISCHR(mode) || S_ISFIFO(mode); }

// /dev/full, /dev/null, a FIFO: written where they are, since renaming a file
// over them would replace the device node. Opened without O_CREAT and without
// following a link, and checked again once open.
bool write_in_place(const std::string& path, std::string_view bytes, std::string* error) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_NOFOLLOW | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return *error = "cannot write " + path + ": " + std::strerror(errno), false;
  struct stat st {};
  int failure = 0;
  if (::fstat(fd, &st) != 0)
    failure = errno;
  else if (!is_stream(st.st_mode))
    failure = EEXIST;  // replaced by a file between the look and the open
  while (failure == 0 && !bytes.empty()) {
    const ssize_t put = ::write(fd, bytes.data(), bytes.size());
    if (put < 0 && errno == EINTR) continue;
    if (put <= 0) failure = put == 0 ? EIO : errno;
    if (put > 0) bytes.remove_prefix(static_cast<size_t>(put));
  }
  if (::close(fd) != 0 && failure == 0) failure = errno;
  if (failure != 0) return *error = "cannot write " + path + ": " + std::strerror(failure), false;
  return true;
}

}  // namespace

bool write_output_file(const std::string& path, std::string_view bytes, std::string* error) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0 && is_stream(st.st_mode)) return write_in_place(path, bytes, error);
  return hal::write_replacing(path, "output file", bytes, 0666, error);
}

}  // namespace sinew::rigc
