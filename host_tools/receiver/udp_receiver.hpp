// Receives a sinew UDP stream on a local port and hands out decoded frames.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hal/output/pose_decode.hpp"
#include "reassembler.hpp"

namespace sinew::receiver {

struct UdpReceiverOptions {
  std::string bind_address = "0.0.0.0";
  uint16_t port = 0;                   // 0: an ephemeral port (see port())
  int receive_buffer_bytes = 4 << 20;  // SO_RCVBUF: room for bursts of fragments
  ReassemblerOptions reassembly;
};

enum class ReceiveResult : uint8_t { kFrame, kTimeout, kError };

class UdpReceiver {
 public:
  UdpReceiver() = default;
  ~UdpReceiver() { close(); }
  UdpReceiver(const UdpReceiver&) = delete;
  UdpReceiver& operator=(const UdpReceiver&) = delete;

  bool open(const UdpReceiverOptions& options, std::string* error);
  void close();
  uint16_t port() const { return port_; }

  // Receives until a frame completes and decodes (kFrame, into *out), or
  // `timeout_ms` passes (kTimeout), or the socket fails (kError, *error set).
  // Frames that reassemble but do not decode are counted and skipped.
  ReceiveResult receive(int timeout_ms, hal::output::DecodedPose* out, std::string* error);

  uint64_t sequence() const { return reassembler_.frame_sequence(); }  // of the last frame returned
  const ReceiverStats& stats() const { return reassembler_.stats(); }
  uint64_t undecodable_frames() const { return undecodable_; }
  std::string summary() const;

 private:
  int fd_ = -1;
  uint16_t port_ = 0;
  Reassembler reassembler_;
  std::vector<uint8_t> datagram_;
  uint64_t undecodable_ = 0;
};

}  // namespace sinew::receiver
