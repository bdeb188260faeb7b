#include "socketcan_source.hpp"

#include <errno.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <cstring>

#include "kernel_frame.hpp"

namespace sinew::hal::can {

namespace {

uint64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1'000'000'000u + static_cast<uint64_t>(ts.tv_nsec);
}

bool set_error(std::string* error, const std::string& what, int err) {
  if (error != nullptr) *error = what + ": " + std::strerror(err);
  return false;
}

}  // namespace

SocketCanSource::SocketCanSource(SocketCanOptions options)
    : options_(std::move(options)), name_("socketcan:" + options_.interface), backoff_(options_.backoff) {}

SocketCanSource::~SocketCanSource() { close_socket(); }

void SocketCanSource::close_socket() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool SocketCanSource::open(uint64_t now_ns, std::string* error) {
  if (try_open(error)) return true;
  went_down(last_errno_, now_ns);
  return false;
}

bool SocketCanSource::try_open(std::string* error) {
  close_socket();
  const std::string& ifname = options_.interface;
  if (ifname.empty() || ifname.size() >= IFNAMSIZ) {
    last_errno_ = EINVAL;
    return set_error(error, "interface name '" + ifname + "'", EINVAL);
  }
  const int s = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (s < 0) {
    last_errno_ = errno;
    return set_error(error, "socket(PF_CAN, SOCK_RAW, CAN_RAW)", last_errno_);
  }
  fd_ = s;
  auto fail = [&](const std::string& what) {
    last_errno_ = errno;
    close_socket();
    return set_error(error, what, last_errno_);
  };

  ifreq ifr{};
  std::memcpy(ifr.ifr_name, ifname.c_str(), ifname.size() + 1);
  if (::ioctl(fd_, SIOCGIFINDEX, &ifr) < 0) return fail("interface " + ifname);
  const int ifindex = ifr.ifr_ifindex;
  // A socket bound to a down interface opens fine and stays silent; report
  // it as down so the caller sees why nothing arrives.
  if (::ioctl(fd_, SIOCGIFFLAGS, &ifr) < 0) return fail("SIOCGIFFLAGS " + ifname);
  if ((ifr.ifr_flags & IFF_UP) == 0) {
    errno = ENETDOWN;
    return fail("interface " + ifname);
  }

  const int one = 1;
  if (options_.fd && ::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &one, sizeof one) < 0) {
    return fail("CAN_RAW_FD_FRAMES");
  }
  if (options_.error_frames) {
    const can_err_mask_t mask = CAN_ERR_MASK;
    if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &mask, sizeof mask) < 0) return fail("CAN_RAW_ERR_FILTER");
  }
  if (!apply_filters(error)) {
    last_errno_ = errno;
    close_socket();
    return false;
  }
  // Kernel receive timestamps; fall back to microseconds where ns is missing.
  if (::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one) < 0 &&
      ::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMP, &one, sizeof one) < 0) {
    return fail("SO_TIMESTAMP");
  }
  if (::setsockopt(fd_, SOL_SOCKET, SO_RXQ_OVFL, &one, sizeof one) < 0) return fail("SO_RXQ_OVFL");
  if (options_.receive_buffer_bytes > 0 && ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &options_.receive_buffer_bytes,
                                                        sizeof options_.receive_buffer_bytes) < 0) {
    return fail("SO_RCVBUF");
  }

  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifindex;
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) < 0) return fail("bind " + ifname);

  last_drop_count_ = 0;
  last_errno_ = 0;
  backoff_.succeeded();
  if (ever_opened_) ++tracker_.counters().reopens;
  ever_opened_ = true;
  tracker_.on_interface_up();
  return true;
}

bool SocketCanSource::set_filters(std::span<const FrameId> ids, std::string* error) {
  filters_ = kernel_filters(ids);
  filters_set_ = true;
  return fd_ < 0 || apply_filters(error);
}

bool SocketCanSource::apply_filters(std::string* error) {
  if (!filters_set_ || filters_.empty()) return true;     // default: receive everything
  if (filters_.size() > CAN_RAW_FILTER_MAX) return true;  // too many for the kernel: the decoder rejects strays
  const auto bytes = static_cast<socklen_t>(filters_.size() * sizeof(can_filter));
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, filters_.data(), bytes) < 0) {
    return set_error(error, "CAN_RAW_FILTER", errno);
  }
  return true;
}

void SocketCanSource::went_down(int err, uint64_t now_ns) {
  last_errno_ = err;
  close_socket();
  tracker_.on_interface_down();
  backoff_.failed(now_ns);
}

size_t SocketCanSource::drain(std::span<CanFrame> out, uint64_t now_ns) {
  if (fd_ < 0) {
    if (!backoff_.due(now_ns)) return 0;
    ++tracker_.counters().reopen_attempts;
    if (!try_open(nullptr)) {
      went_down(last_errno_, now_ns);
      return 0;
    }
  }
  // Kernel timestamps are CLOCK_REALTIME; shift them onto CLOCK_MONOTONIC with
  // the offset sampled once per drain (a clock step between reception and
  // this drain shifts those frames by the step).
  const auto realtime_minus_monotonic =
      static_cast<int64_t>(clock_ns(CLOCK_REALTIME)) - static_cast<int64_t>(clock_ns(CLOCK_MONOTONIC));

  size_t n = 0;
  while (n < out.size()) {
    canfd_frame raw;
    iovec iov{&raw, sizeof raw};
    alignas(cmsghdr) unsigned char
        control[CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(timeval)) + CMSG_SPACE(sizeof(uint32_t))];
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof control;
    const ssize_t got = ::recvmsg(fd_, &msg, MSG_DONTWAIT);
    if (got < 0) {
      const int err = errno;
      if (err == EAGAIN || err == EWOULDBLOCK) break;
      if (err == EINTR) continue;
      if (err != ENETDOWN && err != ENODEV) ++tracker_.counters().read_errors;
      went_down(err, now_ns);
      break;
    }
    uint64_t stamp_ns = 0;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level != SOL_SOCKET) continue;
      if (c->cmsg_type == SCM_TIMESTAMPNS) {
        timespec ts;
        std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
        stamp_ns = static_cast<uint64_t>(ts.tv_sec) * 1'000'000'000u + static_cast<uint64_t>(ts.tv_nsec);
      } else if (c->cmsg_type == SCM_TIMESTAMP) {
        timeval tv;
        std::memcpy(&tv, CMSG_DATA(c), sizeof tv);
        stamp_ns = static_cast<uint64_t>(tv.tv_sec) * 1'000'000'000u + static_cast<uint64_t>(tv.tv_usec) * 1000u;
      } else if (c->cmsg_type == SO_RXQ_OVFL) {
        uint32_t drops = 0;
        std::memcpy(&drops, CMSG_DATA(c), sizeof drops);
        tracker_.counters().dropped +=
            static_cast<uint32_t>(drops - last_drop_count_);  // wraps like the kernel's counter
        last_drop_count_ = drops;
      }
    }
    const int64_t mono = static_cast<int64_t>(stamp_ns) - realtime_minus_monotonic;
    const uint64_t timestamp = stamp_ns != 0 && mono > 0 ? static_cast<uint64_t>(mono) : now_ns;
    CanFrame& f = out[n];
    if ((msg.msg_flags & MSG_TRUNC) != 0 || !from_kernel(&raw, static_cast<size_t>(got), timestamp, f)) {
      ++tracker_.counters().read_errors;
      continue;
    }
    if (f.kind == FrameKind::kError) {
      tracker_.on_error_frame(f);
    } else {
      tracker_.on_frame_received();
    }
    ++n;
  }
  return n;
}

}  // namespace sinew::hal::can
