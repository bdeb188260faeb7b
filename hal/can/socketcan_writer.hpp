// Sends CAN frames on a SocketCAN interface: a CAN_RAW socket that receives
// nothing (an empty CAN_RAW_FILTER), non-blocking writes of whole frames as
// can-utils' cansend does, and reopen with back-off when the interface
// goes away. A full transmit queue (ENOBUFS, EAGAIN) drops the rest of the
// tick's frames rather than block the caller; the counters say how many.
#pragma once

#include <cstdint>
#include <string>

#include "frame_writer.hpp"
#include "reopen_backoff.hpp"

namespace sinew::hal::can {

struct SocketCanWriterOptions {
  std::string interface = "can0";
  BackoffPolicy backoff;
};

class SocketCanWriter final : public FrameWriter {
 public:
  explicit SocketCanWriter(SocketCanWriterOptions options);
  ~SocketCanWriter() override;
  SocketCanWriter(const SocketCanWriter&) = delete;
  SocketCanWriter& operator=(const SocketCanWriter&) = delete;

  // First open, at configuration time: false (error says why) when the
  // interface does not exist or is not CAN. Later failures reopen with
  // back-off from send().
  bool open(std::string* error);

  const char* name() const override { return options_.interface.c_str(); }
  size_t send(std::span<const CanFrame> frames, uint64_t now_ns) override;
  uint64_t frames_sent() const override { return sent_; }
  uint64_t frames_dropped() const override { return dropped_; }
  std::string status_line() const override;

  int fd() const { return fd_; }  // -1 while down
  int last_errno() const { return last_errno_; }

 private:
  bool try_open(std::string* error);
  void close_socket();

  SocketCanWriterOptions options_;
  ReopenBackoff backoff_;
  int fd_ = -1;
  int last_errno_ = 0;
  uint64_t sent_ = 0;
  uint64_t dropped_ = 0;
  uint64_t reopens_ = 0;
};

}  // namespace sinew::hal::can
