// Hands each frame, without its vertices, to the sink it wraps: for sinks
// that carry the inputs only (a recording, the CAN pose frames), so that the
// I/O thread's ring in front of them holds inputs-only slots. Per tick no
// allocation: a copy of pointers.
#pragma once

#include <memory>
#include <string>
#include <utility>

#include "hal/common/output_sink.hpp"

namespace sinew::firmware {

class InputsOnlySink : public hal::OutputSink {
 public:
  // label: prefixes the status line ("" for none).
  InputsOnlySink(std::unique_ptr<hal::OutputSink> inner, std::string label)
      : inner_(std::move(inner)), label_(std::move(label)) {}
  const char* name() const override { return inner_->name(); }
  bool write(const hal::PoseFrame& frame) override {
    hal::PoseFrame inputs_only = frame;
    inputs_only.vertex_count = 0;
    for (int c = 0; c < 3; ++c) inputs_only.position[c] = inputs_only.normal[c] = nullptr;
    return inner_->write(inputs_only);
  }
  void flush() override { inner_->flush(); }
  void close() override { inner_->close(); }
  uint64_t frames_lost_after_write() const override { return inner_->frames_lost_after_write(); }
  std::string status_line() const override {
    return label_.empty() ? inner_->status_line() : label_ + ": " + inner_->status_line();
  }

 private:
  std::unique_ptr<hal::OutputSink> inner_;
  std::string label_;
};

}  // namespace sinew::firmware
