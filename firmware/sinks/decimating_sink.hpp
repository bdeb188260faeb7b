// Keeps one frame in n for the sink it wraps: the frames whose tick is a
// multiple of n (so a decimated log lines up with the tick numbers of the
// run, and a render of a recording decimated the same way matches it).
#pragma once

#include <memory>

#include "hal/common/output_sink.hpp"

namespace sinew::firmware {

class DecimatingSink final : public hal::OutputSink {
 public:
  DecimatingSink(std::unique_ptr<hal::OutputSink> inner, uint64_t every_n)
      : inner_(std::move(inner)), every_n_(every_n < 1 ? 1 : every_n) {}
  const char* name() const override { return inner_->name(); }
  bool write(const hal::PoseFrame& frame) override { return frame.tick % every_n_ != 0 || inner_->write(frame); }
  void flush() override { inner_->flush(); }
  void close() override { inner_->close(); }
  uint64_t frames_lost_after_write() const override { return inner_->frames_lost_after_write(); }
  std::string status_line() const override {
    return inner_->status_line() + " (one frame in " + std::to_string(every_n_) + ")";
  }

 private:
  std::unique_ptr<hal::OutputSink> inner_;
  uint64_t every_n_;
};

}  // namespace sinew::firmware
