#include "socketcan_writer.hpp"

#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "kernel_frame.hpp"

namespace sinew::hal::can {

SocketCanWriter::SocketCanWriter(SocketCanWriterOptions options)
    : options_(std::move(options)), backoff_(options_.backoff) {}

SocketCanWriter::~SocketCanWriter() { close_socket(); }

void SocketCanWriter::close_socket() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool SocketCanWriter::try_open(std::string* error) {
  const auto fail = [&](const char* what) {
    last_errno_ = errno;
    if (error != nullptr)
      *error = "CAN interface " + options_.interface + ": " + what + ": " + std::strerror(last_errno_);
    close_socket();
    return false;
  };
  if (options_.interface.empty() || options_.interface.size() >= IFNAMSIZ) {
    errno = EINVAL;
    return fail("interface name");
  }
  fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd_ < 0) return fail("socket");
  // A sender only: no filter entry, so the socket queues nothing it would
  // have to drain.
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, nullptr, 0) != 0) return fail("CAN_RAW_FILTER");
  const unsigned index = ::if_nametoindex(options_.interface.c_str());
  if (index == 0) return fail("no such interface");
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(index);
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) return fail("bind");
  return true;
}

bool SocketCanWriter::open(std::string* error) {
  if (try_open(error)) {
    backoff_.succeeded();
    return true;
  }
  return false;
}

size_t SocketCanWriter::send(std::span<const CanFrame> frames, uint64_t now_ns) {
  if (fd_ < 0) {
    if (!backoff_.due(now_ns) || !try_open(nullptr)) {
      backoff_.failed(now_ns);
      dropped_ += frames.size();
      return 0;
    }
    backoff_.succeeded();
    ++reopens_;
  }
  size_t sent = 0;
  for (const CanFrame& f : frames) {
    canfd_frame kernel{};
    const size_t bytes = to_kernel(f, kernel);
    if (bytes == 0) break;  // not well formed: dropped with the rest
    const ssize_t n = ::write(fd_, &kernel, bytes);
    if (n == static_cast<ssize_t>(bytes)) {
      ++sent;
      continue;
    }
    last_errno_ = n < 0 ? errno : EIO;
    // The interface went away or down: reopen later. A full queue
    // (ENOBUFS, EAGAIN) keeps the socket; this tick's rest is dropped.
    if (last_errno_ == ENODEV || last_errno_ == ENXIO || last_errno_ == ENETDOWN) {
      close_socket();
      backoff_.failed(now_ns);
    }
    break;
  }
  sent_ += sent;
  dropped_ += frames.size() - sent;
  return sent;
}

std::string SocketCanWriter::status_line() const {
  std::string s = "can " + options_.interface + (fd_ >= 0 ? " up" : " down") + ": sent " + std::to_string(sent_) +
                  ", dropped " + std::to_string(dropped_);
  if (reopens_ > 0) s += ", reopened " + std::to_string(reopens_);
  if (last_errno_ != 0) s += ", last error " + std::string(std::strerror(last_errno_));
  return s;
}

}  // namespace sinew::hal::can
