// One [[sink]] that feeds several outputs (the dds sink's joint states every
// tick and its mesh at a lower rate): each frame goes to every inner sink in
// order, each with its own ring and I/O thread. Per tick no allocation.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "hal/common/output_sink.hpp"

namespace sinew::firmware {

class FanOutSink : public hal::OutputSink {
 public:
  FanOutSink(std::string name, std::vector<std::unique_ptr<hal::OutputSink>> inner)
      : name_(std::move(name)), inner_(std::move(inner)) {}
  const char* name() const override { return name_.c_str(); }
  // False when any inner sink dropped the frame (each counts its own).
  bool write(const hal::PoseFrame& frame) override {
    bool all = true;
    for (const auto& s : inner_) all = s->write(frame) && all;
    return all;
  }
  void flush() override {
    for (const auto& s : inner_) s->flush();
  }
  void close() override {
    for (const auto& s : inner_) s->close();
  }
  uint64_t frames_lost_after_write() const override {
    uint64_t lost = 0;
    for (const auto& s : inner_) lost += s->frames_lost_after_write();
    return lost;
  }
  std::string status_line() const override {
    std::string line;
    for (const auto& s : inner_) line += (line.empty() ? "" : "; ") + s->status_line();
    return line;
  }

 private:
  std::string name_;
  std::vector<std::unique_ptr<hal::OutputSink>> inner_;
};

}  // namespace sinew::firmware
