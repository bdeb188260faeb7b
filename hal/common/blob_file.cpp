#include "blob_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
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

namespace {

// Reads exactly `size` bytes from the start of the file (the first read is
// at offset 0); false with a message on a short or failed read.
bool read_exactly(int fd, const std::string& path, uint8_t* dst, size_t size, std::string* error) {
  size_t done = 0;
  while (done < size) {
    const ssize_t n = ::pread(fd, dst + done, size - done, static_cast<off_t>(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      return *error = path + ": read failed" + (n < 0 ? std::string(": ") + std::strerror(errno) : " (file shrank)"),
             false;
    done += static_cast<size_t>(n);
  }
  return true;
}

}  // namespace

bool read_blob_file(const std::string& path, size_t max_bytes, BlobBytes* out, std::string* error, PrefixCheck prefix) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return *error = path + ": cannot open: " + std::strerror(errno), false;
  struct stat st {};
  bool ok = ::fstat(fd, &st) == 0;
  if (!ok) *error = path + ": cannot stat: " + std::strerror(errno);
  if (ok && S_ISDIR(st.st_mode)) ok = false, *error = path + ": is a directory, not a rig file";
  if (ok && !S_ISREG(st.st_mode)) ok = false, *error = path + ": not a regular file";
  if (ok && static_cast<uint64_t>(st.st_size) > max_bytes)
    ok = false, *error = path + ": larger than " + std::to_string(max_bytes) + " bytes";
  const size_t size = ok ? static_cast<size_t>(st.st_size) : 0;
  if (ok && prefix.check != nullptr) {
    std::vector<uint8_t> head(std::min(prefix.bytes, size));
    std::string why;
    ok = read_exactly(fd, path, head.data(), head.size(), error);
    if (ok && !prefix.check(head.data(), head.size(), size, &why)) ok = false, *error = path + ": " + why;
  }
  BlobBytes b;
  if (ok) {
    b.words.assign(size / 8 + 1, 0);
    ok = read_exactly(fd, path, reinterpret_cast<uint8_t*>(b.words.data()), size, error);
    b.size = size;
  }
  ::close(fd);
  if (ok) *out = std::move(b);
  return ok;
}

}  // namespace sinew::hal
