// SocketCAN backend: a thin wrapper over the kernel's CAN_RAW socket, in the
// way can-utils' candump uses it. Non-blocking drain with recvmsg, kernel
// receive timestamps (SO_TIMESTAMPNS, converted to CLOCK_MONOTONIC), drop
// counts (SO_RXQ_OVFL), identifier filters (CAN_RAW_FILTER), every error
// class (CAN_RAW_ERR_FILTER) feeding the bus state, optional CAN FD
// (CAN_RAW_FD_FRAMES), and reopen with back-off when the interface goes away.
#pragma once

#include <linux/can.h>

#include <cstdint>
#include <string>
#include <vector>

#include "frame_source.hpp"
#include "reopen_backoff.hpp"

namespace sinew::hal::can {

struct SocketCanOptions {
  std::string interface = "can0";
  bool fd = false;               // receive CAN FD frames too
  bool error_frames = true;      // subscribe to all error classes
  int receive_buffer_bytes = 0;  // SO_RCVBUF; 0 keeps the kernel default
  BackoffPolicy backoff;
};

class SocketCanSource final : public FrameSource {
 public:
  explicit SocketCanSource(SocketCanOptions options);
  ~SocketCanSource() override;
  SocketCanSource(const SocketCanSource&) = delete;
  SocketCanSource& operator=(const SocketCanSource&) = delete;

  // First open, at configuration time. On failure the source stays down,
  // `error` says why, and drain() keeps retrying with back-off.
  bool open(uint64_t now_ns, std::string* error);

  const char* name() const override { return name_.c_str(); }
  bool set_filters(std::span<const FrameId> ids, std::string* error) override;
  size_t drain(std::span<CanFrame> out, uint64_t now_ns) override;
  BusState bus_state() const override { return tracker_.state(); }
  const BusCounters& counters() const override { return tracker_.counters(); }

  int fd() const { return fd_; }  // for poll()/epoll; -1 while down
  int last_errno() const { return last_errno_; }

 private:
  bool try_open(std::string* error);
  bool apply_filters(std::string* error);
  void close_socket();
  void went_down(int err, uint64_t now_ns);

  SocketCanOptions options_;
  std::string name_;
  std::vector<can_filter> filters_;
  bool filters_set_ = false;
  BusStateTracker tracker_;
  ReopenBackoff backoff_;
  int fd_ = -1;
  int last_errno_ = 0;
  uint32_t last_drop_count_ = 0;  // SO_RXQ_OVFL is cumulative per socket
  bool ever_opened_ = false;
};

}  // namespace sinew::hal::can
