// The simulated twin of SocketCanWriter: the frames it would send, written
// as a candump log (candump_format.hpp) that candump_parser, the candump
// replay source and can-utils' canplayer read back. Each line carries the
// send time and the interface name the configuration gives.
#pragma once

#include <string>

#include "candump_writer.hpp"
#include "frame_writer.hpp"

namespace sinew::hal::can {

class CandumpFrameWriter final : public FrameWriter {
 public:
  // Creates the log anew (CandumpWriter::open's rules). Configuration time.
  bool open(const std::string& path, const std::string& interface, std::string* error);

  const char* name() const override { return interface_.c_str(); }
  size_t send(std::span<const CanFrame> frames, uint64_t now_ns) override;
  void flush() override { writer_.flush(); }
  uint64_t frames_sent() const override { return sent_; }
  uint64_t frames_dropped() const override { return dropped_; }
  std::string status_line() const override;

 private:
  CandumpWriter writer_;
  std::string interface_;
  uint64_t sent_ = 0;
  uint64_t dropped_ = 0;
};

}  // namespace sinew::hal::can
