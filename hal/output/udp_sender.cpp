#include "udp_sender.hpp"

#include <netdb.h>
#include <sys/random.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "pose_codec.hpp"

namespace sinew::hal::output {

namespace {

constexpr uint32_t kMaxUdpDatagram = 65507;  // largest IPv4 UDP payload

uint32_t random_stream_id() {
  uint32_t id = 0;
  if (::getrandom(&id, sizeof(id), GRND_NONBLOCK) != static_cast<ssize_t>(sizeof(id)))
    id = static_cast<uint32_t>(::getpid());  // no entropy yet (early boot): still differs per run
  return id == 0 ? 1 : id;
}

int connect_udp(const std::string& host, uint16_t port, std::string* error) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  const int rc = ::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found);
  if (rc != 0) return *error = "cannot resolve " + host + ": " + ::gai_strerror(rc), -1;
  int fd = -1;
  for (const addrinfo* a = found; a != nullptr && fd < 0; a = a->ai_next) {
    fd = ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
    if (fd >= 0 && ::connect(fd, a->ai_addr, a->ai_addrlen) != 0) {
      *error = "cannot connect to " + host + ": " + std::strerror(errno);
      ::close(fd);
      fd = -1;
    }
  }
  ::freeaddrinfo(found);
  if (fd < 0 && error->empty()) *error = "no usable address for " + host;
  return fd;
}

}  // namespace

bool UdpSender::open(const std::string& host, uint16_t port, const FrameShape& shape, const UdpSenderOptions& options,
                     std::string* error) {
  close();
  stats_ = {};
  shape_ = shape;
  const uint64_t max_payload = max_pose_payload_bytes(shape);
  if (max_payload == 0) return *error = "frame too large for the UDP stream", false;
  if (options.max_datagram_bytes <= kUdpHeaderBytes || options.max_datagram_bytes > kMaxUdpDatagram)
    return *error = "max datagram size must be in (" + std::to_string(kUdpHeaderBytes) + ", " +
                    std::to_string(kMaxUdpDatagram) + "]",
           false;
  fragment_bytes_ = options.max_datagram_bytes - kUdpHeaderBytes;
  const uint64_t max_fragments = (max_payload + fragment_bytes_ - 1) / fragment_bytes_;
  if (max_fragments > UINT16_MAX) return *error = "frame needs more than 65535 fragments", false;

  error->clear();
  fd_ = connect_udp(host, port, error);
  if (fd_ < 0) return false;
  if (options.send_buffer_bytes > 0 &&
      ::setsockopt(fd_, SOL_SOCKET, SO_SNDBUF, &options.send_buffer_bytes, sizeof(int)) != 0) {
    *error = std::string("cannot set the send buffer: ") + std::strerror(errno);
    return close(), false;
  }
  stream_id_ = options.stream_id != 0 ? options.stream_id : random_stream_id();
  sequence_ = 0;
  payload_.assign(static_cast<size_t>(max_payload), 0);
  headers_.assign(static_cast<size_t>(max_fragments) * kUdpHeaderBytes, 0);
  iov_.assign(static_cast<size_t>(max_fragments) * 2, iovec{});
  messages_.assign(static_cast<size_t>(max_fragments), mmsghdr{});
  return true;
}

void UdpSender::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool UdpSender::write(const PoseFrame& frame) {
  const uint64_t sequence = sequence_++;
  if (fd_ < 0) return ++stats_.frames_dropped, false;
  const size_t n = encode_pose(frame, shape_, payload_);
  if (n == 0) return ++stats_.frames_rejected, false;

  const size_t count = (n + fragment_bytes_ - 1) / fragment_bytes_;
  UdpFragment f;
  f.stream_id = stream_id_;
  f.sequence = sequence;
  f.fragment_count = static_cast<uint16_t>(count);
  f.total_bytes = static_cast<uint32_t>(n);
  unsigned queued = 0;
  for (size_t i = 0; i < count; ++i) {
    const size_t offset = i * fragment_bytes_;
    const std::span<const uint8_t> part(payload_.data() + offset, std::min(fragment_bytes_, n - offset));
    f.fragment_index = static_cast<uint16_t>(i);
    f.payload_offset = static_cast<uint32_t>(offset);
    f.payload_bytes = static_cast<uint16_t>(part.size());
    uint8_t* header = headers_.data() + i * kUdpHeaderBytes;
    write_udp_header(f, part, header);
    if (static_cast<int>(i) == skip_fragment_) continue;
    iovec* iov = &iov_[2 * queued];
    iov[0] = {header, kUdpHeaderBytes};
    iov[1] = {const_cast<uint8_t*>(part.data()), part.size()};  // iovec is not const-correct; only read
    messages_[queued] = mmsghdr{};
    messages_[queued].msg_hdr.msg_iov = iov;
    messages_[queued].msg_hdr.msg_iovlen = 2;
    ++queued;
  }

  unsigned sent = 0;
  while (sent < queued) {
    const int r = ::sendmmsg(fd_, messages_.data() + sent, queued - sent, MSG_DONTWAIT);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) {  // EAGAIN: socket buffer full; anything else: send error. Either way, not this tick.
      stats_.last_errno = r < 0 ? errno : EIO;
      stats_.datagrams_sent += sent;
      return ++stats_.frames_dropped, false;
    }
    sent += static_cast<unsigned>(r);
  }
  stats_.datagrams_sent += sent;
  ++stats_.frames_sent;
  return true;
}

std::string UdpSender::status_line() const {
  std::string s = std::string(name()) + ": stream " + std::to_string(stream_id_) + ", " +
                  std::to_string(stats_.frames_sent) + " sent, " + std::to_string(stats_.frames_dropped) +
                  " dropped, " + std::to_string(stats_.frames_rejected) + " rejected, " +
                  std::to_string(stats_.datagrams_sent) + " datagrams";
  if (stats_.last_errno != 0) s += ", last error: " + std::string(std::strerror(stats_.last_errno));
  return s;
}

}  // namespace sinew::hal::output
