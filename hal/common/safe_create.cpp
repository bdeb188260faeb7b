#include "safe_create.hpp"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstring>

namespace sinew::hal {

namespace {

std::string errno_text() { return std::strerror(errno); }

// Unpredictable, so another user cannot plant links under the names a writer
// will try next; O_EXCL makes a collision a retry, never a hazard.
uint64_t random_bits() {
  uint64_t bits = 0;
  if (::getrandom(&bits, sizeof(bits), GRND_NONBLOCK) == static_cast<ssize_t>(sizeof(bits))) return bits;
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  static uint64_t counter = 0;
  return (static_cast<uint64_t>(ts.tv_nsec) << 20) ^ static_cast<uint64_t>(ts.tv_sec) ^
         (static_cast<uint64_t>(::getpid()) << 40) ^ ++counter;
}

const char* file_kind(mode_t mode) {
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

bool write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t put = ::write(fd, bytes.data(), bytes.size());
    if (put < 0 && errno == EINTR) continue;
    if (put <= 0) {
      if (put == 0) errno = EIO;
      return false;
    }
    bytes.remove_prefix(static_cast<size_t>(put));
  }
  return true;
}

}  // namespace

OutputDir::~OutputDir() {
  discard();
  if (dir_fd_ >= 0) ::close(dir_fd_);
}

std::string OutputDir::subject() const { return what_ + " " + path_; }

std::string OutputDir::refuse(const std::string& problem) const { return subject() + ": " + problem; }

bool OutputDir::open(const std::string& path, std::string_view what, std::string* error) {
  what_ = what;
  path_ = path;
  const size_t slash = path.rfind('/');
  dir_ = slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
  name_ = slash == std::string::npos ? path : path.substr(slash + 1);
  if (name_.empty() || name_ == "." || name_ == "..") return *error = refuse("does not name a file"), false;

  // The directory itself is resolved normally: which directory is the caller's choice.
  dir_fd_ = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd_ < 0) return *error = refuse("cannot open its directory " + dir_ + ": " + errno_text()), false;
  struct stat st {};
  if (::fstat(dir_fd_, &st) != 0)
    return *error = refuse("cannot stat its directory " + dir_ + ": " + errno_text()), false;
  dir_world_writable_ = (st.st_mode & S_IWOTH) != 0;
  dir_owner_ = st.st_uid;
  if (dir_world_writable_ && (st.st_mode & S_ISVTX) == 0)
    return *error = refuse("directory " + dir_ +
                           " is writable by every user and has no sticky bit, so anyone could replace the file: "
                           "refusing it"),
           false;
  return true;
}

bool OutputDir::check_existing(const struct stat& st, bool in_place, std::string* error) const {
  if (S_ISLNK(st.st_mode)) return *error = refuse("is a symbolic link, refusing to follow it"), false;
  if (!S_ISREG(st.st_mode))
    return *error = refuse(std::string("is ") + file_kind(st.st_mode) + ", not a regular file"), false;
  // Writing in place through a second name would change the file under its other name too.
  if (in_place && st.st_nlink > 1)
    return *error = refuse("has " + std::to_string(st.st_nlink) +
                           " names (hard links), refusing to write to a file that is also elsewhere"),
           false;
  if (dir_world_writable_ && st.st_uid != ::geteuid() && st.st_uid != dir_owner_)
    return *error = refuse("belongs to uid " + std::to_string(st.st_uid) + " in world-writable directory " + dir_ +
                           (in_place ? ", refusing to write to" : ", refusing to replace") + " another user's file"),
           false;
  return true;
}

int OutputDir::open_existing(int flags, bool* missing, std::string* error) {
  *missing = false;
  // O_NONBLOCK: a FIFO planted at the name must not block the open; it is refused below.
  const int fd = ::openat(dir_fd_, name_.c_str(), flags | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) {
    if (errno == ENOENT) return *missing = true, -1;
    if (errno == ELOOP) return *error = refuse("is a symbolic link, refusing to follow it"), -1;
    return *error = refuse("cannot open: " + errno_text()), -1;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    *error = refuse("cannot stat: " + errno_text());
    return ::close(fd), -1;
  }
  if (!check_existing(st, true, error)) return ::close(fd), -1;
  const int status = ::fcntl(fd, F_GETFL);
  if (status < 0 || ::fcntl(fd, F_SETFL, status & ~O_NONBLOCK) != 0) {
    *error = refuse("cannot set blocking mode: " + errno_text());
    return ::close(fd), -1;
  }
  return fd;
}

bool OutputDir::check_replaceable(std::string* error) {
  struct stat st {};
  if (::fstatat(dir_fd_, name_.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) {
    if (errno == ENOENT) return true;
    return *error = refuse("cannot stat: " + errno_text()), false;
  }
  return check_existing(st, false, error);
}

int OutputDir::create_temp(mode_t mode, std::string* error) {
  discard();
  constexpr int kAttempts = 16;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    char suffix[24];
    std::snprintf(suffix, sizeof(suffix), ".%016" PRIx64 ".tmp", random_bits());
    const std::string temp = "." + name_ + suffix;
    // O_EXCL|O_NOFOLLOW: whatever is already at that name (a planted link too) makes this fail, never opens it.
    const int fd = ::openat(dir_fd_, temp.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, mode);
    if (fd >= 0) return temp_ = temp, fd;
    if (errno != EEXIST) return *error = refuse("cannot create a temporary file in " + dir_ + ": " + errno_text()), -1;
  }
  return *error = refuse("cannot create a temporary file in " + dir_ + ": every name tried was taken"), -1;
}

bool OutputDir::commit(std::string* error) {
  if (temp_.empty()) return *error = refuse("no temporary file to rename into place"), false;
  if (::renameat(dir_fd_, temp_.c_str(), dir_fd_, name_.c_str()) != 0)
    return *error = refuse("cannot rename " + temp_ + " into place: " + errno_text()), false;
  temp_.clear();
  // A renamed entry is durable only once its directory is synced. Some file
  // systems cannot sync a directory; the rename itself has happened then.
  ::fsync(dir_fd_);
  return true;
}

void OutputDir::discard() {
  if (temp_.empty()) return;
  ::unlinkat(dir_fd_, temp_.c_str(), 0);
  temp_.clear();
}

int create_replacing(const std::string& path, std::string_view what, mode_t mode, std::string* error) {
  OutputDir dir;
  if (!dir.open(path, what, error) || !dir.check_replaceable(error)) return -1;
  const int fd = dir.create_temp(mode, error);
  if (fd < 0) return -1;
  if (!dir.commit(error)) return ::close(fd), -1;
  return fd;
}

bool write_replacing(const std::string& path, std::string_view what, std::string_view bytes, mode_t mode,
                     std::string* error) {
  OutputDir dir;
  if (!dir.open(path, what, error) || !dir.check_replaceable(error)) return false;
  const int fd = dir.create_temp(mode, error);
  if (fd < 0) return false;
  int failure = 0;
  if (!write_all(fd, bytes) || ::fsync(fd) != 0) failure = errno;
  if (::close(fd) != 0 && failure == 0) failure = errno;
  // On failure the destructor removes the temporary file: nothing is left behind.
  if (failure != 0) return *error = dir.subject() + ": cannot write: " + std::strerror(failure), false;
  return dir.commit(error);
}

}  // namespace sinew::hal
