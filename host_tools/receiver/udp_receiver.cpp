#include "udp_receiver.hpp"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>

namespace sinew::receiver {

namespace {
constexpr size_t kMaxDatagram = 65536;
}

bool UdpReceiver::open(const UdpReceiverOptions& options, std::string* error) {
  close();
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICHOST;
  addrinfo* found = nullptr;
  const int rc = ::getaddrinfo(options.bind_address.c_str(), std::to_string(options.port).c_str(), &hints, &found);
  if (rc != 0) return *error = "bad bind address " + options.bind_address + ": " + ::gai_strerror(rc), false;
  fd_ = ::socket(found->ai_family, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  const bool bound = fd_ >= 0 && ::bind(fd_, found->ai_addr, found->ai_addrlen) == 0;
  ::freeaddrinfo(found);
  if (!bound) {
    *error = "cannot bind " + options.bind_address + ":" + std::to_string(options.port) + ": " + std::strerror(errno);
    return close(), false;
  }
  // Best effort: the kernel caps it at net.core.rmem_max.
  ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &options.receive_buffer_bytes, sizeof(int));
  sockaddr_storage local{};
  socklen_t len = sizeof(local);
  ::getsockname(fd_, reinterpret_cast<sockaddr*>(&local), &len);
  char service[NI_MAXSERV] = {};
  ::getnameinfo(reinterpret_cast<sockaddr*>(&local), len, nullptr, 0, service, sizeof(service), NI_NUMERICSERV);
  port_ = static_cast<uint16_t>(std::atoi(service));
  reassembler_ = Reassembler(options.reassembly);
  datagram_.assign(kMaxDatagram, 0);
  undecodable_ = 0;
  return true;
}

void UdpReceiver::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

ReceiveResult UdpReceiver::receive(int timeout_ms, hal::output::DecodedPose* out, std::string* error) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left < 0) return ReceiveResult::kTimeout;
    pollfd p{fd_, POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(left));
    if (ready < 0 && errno == EINTR) return ReceiveResult::kTimeout;  // let the caller check for a stop request
    if (ready < 0) return *error = std::string("poll: ") + std::strerror(errno), ReceiveResult::kError;
    if (ready == 0) return ReceiveResult::kTimeout;
    const ssize_t n = ::recv(fd_, datagram_.data(), datagram_.size(), MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
    if (n < 0) return *error = std::string("recv: ") + std::strerror(errno), ReceiveResult::kError;
    if (!reassembler_.feed({datagram_.data(), static_cast<size_t>(n)})) continue;
    std::string why;
    if (hal::output::decode_pose(reassembler_.frame_payload(), out, &why)) return ReceiveResult::kFrame;
    ++undecodable_;
  }
}

std::string UdpReceiver::summary() const {
  const ReceiverStats& s = stats();
  return "delivered " + std::to_string(s.frames_delivered) + ", lost " + std::to_string(s.frames_lost) +
         " (incomplete " + std::to_string(s.frames_incomplete) + ", out of order " +
         std::to_string(s.frames_out_of_order) + "), undecodable " + std::to_string(undecodable_) + "; datagrams " +
         std::to_string(s.datagrams) + " (bad " + std::to_string(s.bad_datagrams) + ", duplicate fragments " +
         std::to_string(s.duplicate_fragments) + ", stale fragments " + std::to_string(s.stale_fragments) +
         ", foreign " + std::to_string(s.foreign_datagrams) + "), stream restarts " + std::to_string(s.stream_restarts);
}

}  // namespace sinew::receiver
