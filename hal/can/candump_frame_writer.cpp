#include "candump_frame_writer.hpp"

namespace sinew::hal::can {

bool CandumpFrameWriter::open(const std::string& path, const std::string& interface, std::string* error) {
  interface_ = interface;
  return writer_.open(path, error);
}

size_t CandumpFrameWriter::send(std::span<const CanFrame> frames, uint64_t now_ns) {
  size_t sent = 0;
  for (const CanFrame& f : frames) {
    CanFrame stamped = f;
    stamped.timestamp_ns = now_ns;
    if (!writer_.write(stamped, interface_)) break;
    ++sent;
  }
  sent_ += sent;
  dropped_ += frames.size() - sent;
  return sent;
}

std::string CandumpFrameWriter::status_line() const {
  return "can " + interface_ + " (candump log): sent " + std::to_string(sent_) + ", dropped " +
         std::to_string(dropped_);
}

}  // namespace sinew::hal::can
