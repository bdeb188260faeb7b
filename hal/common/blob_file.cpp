#include "blob_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace sinew::hal {

BlobBytes blob_from_bytes(const uint8_t* bytes, size_t size) {
  BlobBytes b;
  b.words.assign(size / 8 + 1, 0);
  if (size > 0) std::memcpy(b.words.data(), bytes, size);
  b.size = size;
  return b;
}

bool read_blob_file(const std::string& path, size_t max_bytes, BlobBytes* out, std::string* error) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return *error = path + ": cannot open: " + std::strerror(errno), false;
  struct stat st {};
  bool ok = ::fstat(fd, &st) == 0;
  if (!ok) *error = path + ": cannot stat: " + std::strerror(errno);
  if (ok && S_ISDIR(st.st_mode)) ok = false, *error = path + ": is a directory, not a rig file";
  if (ok && !S_ISREG(st.st_mode)) ok = false, *error = path + ": not a regular file";
  if (ok && static_cast<uint64_t>(st.st_size) > max_bytes)
    ok = false, *error = path + ": larger than " + std::to_string(max_bytes) + " bytes";
  BlobBytes b;
  if (ok) {
    const size_t size = static_cast<size_t>(st.st_size);
    b.words.assign(size / 8 + 1, 0);
    auto* dst = reinterpret_cast<uint8_t*>(b.words.data());
    size_t done = 0;
    while (ok && done < size) {
      const ssize_t n = ::read(fd, dst + done, size - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0)
        ok = false,
        *error = path + ": read failed" + (n < 0 ? std::string(": ") + std::strerror(errno) : " (file shrank)");
      else
        done += static_cast<size_t>(n);
    }
    b.size = size;
  }
  ::close(fd);
  if (ok) *out = std::move(b);
  return ok;
}

}  // namespace sinew::hal
