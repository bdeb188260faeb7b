// Streams pose frames over UDP: one datagram per frame when it fits, else
// fragments (docs/frame-formats.md). Non-blocking: when the socket buffer is
// full the rest of the frame is dropped and counted; the tick never waits.
// All datagrams of a frame go out in one sendmmsg() from buffers sized at open().
#pragma once

#include <sys/socket.h>  // mmsghdr
#include <sys/uio.h>     // iovec

#include <cstdint>
#include <string>
#include <vector>

#include "frame_shape.hpp"
#include "hal/common/output_sink.hpp"
#include "hal/common/pose_frame.hpp"
#include "udp_datagram.hpp"

namespace sinew::hal::output {

struct UdpSenderOptions {
  uint32_t max_datagram_bytes = kUdpDefaultMaxDatagram;  // header included
  uint32_t stream_id = 0;                                // 0: random at open()
  int send_buffer_bytes = 0;                             // SO_SNDBUF; 0 keeps the system default
};

struct UdpSenderStats {
  uint64_t frames_sent = 0;
  uint64_t frames_dropped = 0;   // socket buffer full or send error: the frame is incomplete at the receiver
  uint64_t frames_rejected = 0;  // frame does not match the stream's shape
  uint64_t datagrams_sent = 0;
  int last_errno = 0;
};

class UdpSender final : public OutputSink {
 public:
  UdpSender() = default;
  ~UdpSender() override { close(); }
  UdpSender(const UdpSender&) = delete;
  UdpSender& operator=(const UdpSender&) = delete;

  // Resolves host:port (numeric or by name; at open only) and connects a
  // non-blocking UDP socket to it.
  bool open(const std::string& host, uint16_t port, const FrameShape& shape, const UdpSenderOptions& options,
            std::string* error);
  void close() override;

  // Sends one frame; false if rejected or dropped (counted). Every call uses
  // the next sequence number, so a dropped frame is a gap at the receiver.
  // No allocation.
  bool write(const PoseFrame& frame) override;
  void flush() override {}  // nothing is held back: datagrams leave in write()

  bool is_open() const { return fd_ >= 0; }
  uint32_t stream_id() const { return stream_id_; }
  uint64_t next_sequence() const { return sequence_; }
  size_t fragment_payload_bytes() const { return fragment_bytes_; }
  const UdpSenderStats& stats() const { return stats_; }
  // The name in reports ("udp" unless set: the daemon gives the sink's).
  const char* name() const override { return name_.c_str(); }
  void set_name(std::string name) { name_ = std::move(name); }
  std::string status_line() const override;  // allocates: for periodic reports only

  // Test hook: fragment `index` of every frame is prepared but not sent (-1: off).
  void skip_fragment_for_test(int index) { skip_fragment_ = index; }

 private:
  int fd_ = -1;
  FrameShape shape_;
  uint32_t stream_id_ = 0;
  uint64_t sequence_ = 0;
  size_t fragment_bytes_ = 0;  // payload bytes per datagram
  std::vector<uint8_t> payload_;
  std::vector<uint8_t> headers_;  // kUdpHeaderBytes per fragment
  std::vector<iovec> iov_;        // header + payload slice per fragment
  std::vector<mmsghdr> messages_;
  int skip_fragment_ = -1;
  UdpSenderStats stats_;
  std::string name_ = "udp";
};

}  // namespace sinew::hal::output
