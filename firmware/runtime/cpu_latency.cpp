#include "cpu_latency.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace sinew::firmware {

CpuLatencyRequest::~CpuLatencyRequest() { release(); }

void CpuLatencyRequest::release() {
  if (fd_ >= 0) close(fd_);
  fd_ = -1;
}

std::string CpuLatencyRequest::request(int32_t latency_us, const char* device) {
  release();
  const std::string what = "cpu latency " + std::to_string(latency_us) + " us (" + device + "): ";
  const int fd = open(device, O_WRONLY | O_CLOEXEC);
  if (fd < 0) return what + "not applied (" + std::strerror(errno) + ")\n";
  // The device takes the value as a binary int32 (or as hex text); one
  // write of the 4 bytes.
  const ssize_t n = write(fd, &latency_us, sizeof(latency_us));
  if (n != static_cast<ssize_t>(sizeof(latency_us))) {
    const int e = n < 0 ? errno : EIO;
    close(fd);
    return what + "not applied (" + std::strerror(e) + ")\n";
  }
  fd_ = fd;
  return what + "held for the run\n";
}

}  // namespace sinew::firmware
