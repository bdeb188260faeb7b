// Records every frame another source delivers as a candump log, timestamps
// relative to the tick schedule's origin (rounded up to the log's 1 us
// resolution, so a frame stays on the same side of every tick boundary when
// the periods are whole microseconds). Replaying the log with origin 0 in
// replay mode reproduces the live run's ticks bit for bit.
#pragma once

#include <memory>
#include <string>

#include "candump_writer.hpp"
#include "frame_source.hpp"

namespace sinew::hal::can {

class RecordingFrameSource final : public FrameSource {
 public:
  // interface: the name written on each line (e.g. "can0").
  static std::unique_ptr<RecordingFrameSource> create(std::unique_ptr<FrameSource> inner, const std::string& path,
                                                      std::string interface, uint64_t origin_ns, std::string* error);

  const char* name() const override { return inner_->name(); }
  bool set_filters(std::span<const FrameId> ids, std::string* error) override {
    return inner_->set_filters(ids, error);
  }
  size_t drain(std::span<CanFrame> out, uint64_t now_ns) override;
  BusState bus_state() const override { return inner_->bus_state(); }
  const BusCounters& counters() const override { return inner_->counters(); }

  FrameSource& inner() { return *inner_; }
  void flush() { writer_.flush(); }
  uint64_t recorded() const { return writer_.lines_written(); }
  uint64_t failures() const { return writer_.failures(); }

 private:
  RecordingFrameSource() = default;

  std::unique_ptr<FrameSource> inner_;
  CandumpWriter writer_;
  std::string interface_;
  uint64_t origin_ns_ = 0;
};

}  // namespace sinew::hal::can
