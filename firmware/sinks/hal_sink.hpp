// Adapts a hal output (frame log, UDP stream) to the runtime's OutputSink.
// hal cannot depend on firmware, so its sinks share the interface's shape
// (name, write, flush, status_line) without inheriting it.
#pragma once

#include <memory>
#include <string>

#include "firmware/runtime/io.hpp"

namespace sinew::firmware {

template <typename Sink>
class HalSink final : public OutputSink {
 public:
  HalSink(std::unique_ptr<Sink> sink, std::string label) : sink_(std::move(sink)), label_(std::move(label)) {}
  const char* name() const override { return label_.c_str(); }
  bool write(const hal::PoseFrame& frame) override { return sink_->write(frame); }
  void flush() override { sink_->flush(); }
  std::string status_line() const override { return sink_->status_line(); }

 private:
  std::unique_ptr<Sink> sink_;
  std::string label_;
};

}  // namespace sinew::firmware
