#include "simulated_gpio.hpp"

#include <cerrno>

namespace sinew::hal::gpio {

class SimulatedGroup final : public LineGroup {
 public:
  SimulatedGroup(SimulatedGpio* wire, std::span<const uint32_t> offsets)
      : wire_(wire), offsets_(offsets.begin(), offsets.end()) {
    queues_.init(offsets_.size(), wire->fifo_events_);
    for (uint32_t o : offsets_) wire_->owner_[o] = this;
  }
  ~SimulatedGroup() override {
    for (uint32_t o : offsets_) wire_->owner_[o] = nullptr;
  }

  void queue(uint32_t offset, const LineEvent& event) {
    for (size_t i = 0; i < offsets_.size(); ++i)
      if (offsets_[i] == offset && !queues_.push(i, event)) {
        ++wire_->dropped_;
        ++overflows_;
      }
  }

  int read_events(std::span<LineEvent> out) override {
    if (wire_->fail_errno_ != 0) {
      last_error_ = wire_->fail_errno_;
      return -1;
    }
    return static_cast<int>(queues_.pop_oldest(out));
  }
  // The twin never sleeps: "ready" when something is queued, else an immediate timeout.
  WaitResult wait(uint64_t) override {
    if (wire_->fail_errno_ != 0) return last_error_ = wire_->fail_errno_, WaitResult::kError;
    return queues_.empty() ? WaitResult::kTimeout : WaitResult::kReady;
  }
  bool get_levels(std::span<uint8_t> out) override {
    for (size_t i = 0; i < offsets_.size() && i < out.size(); ++i) out[i] = wire_->levels_[offsets_[i]];
    return true;
  }
  int last_error() const override { return last_error_; }
  uint64_t possible_overflows() const override { return overflows_; }

 private:
  SimulatedGpio* wire_;
  uint64_t overflows_ = 0;
  std::vector<uint32_t> offsets_;
  LineQueues queues_;
  int last_error_ = 0;
};

class SimulatedOutput final : public OutputLine {
 public:
  SimulatedOutput(SimulatedGpio* wire, uint32_t offset) : wire_(wire), offset_(offset) { wire_->output_[offset] = 1; }
  ~SimulatedOutput() override { wire_->output_[offset_] = 0; }
  bool set_level(bool high) override {
    wire_->levels_[offset_] = high ? 1 : 0;
    return true;
  }

 private:
  SimulatedGpio* wire_;
  uint32_t offset_;
};

class SimulatedChip final : public GpioChip {
 public:
  explicit SimulatedChip(SimulatedGpio* wire) : wire_(wire) {}
  const char* name() const override { return "simulated-gpio"; }
  uint32_t line_count() const override { return wire_->line_count(); }

  std::unique_ptr<LineGroup> request_inputs(std::span<const uint32_t> offsets, std::string* error) override {
    for (uint32_t o : offsets) {
      if (o >= line_count()) return *error = "line " + std::to_string(o) + " is beyond the chip", nullptr;
      if (wire_->requested(o)) return *error = "line " + std::to_string(o) + " is busy", nullptr;
    }
    return std::make_unique<SimulatedGroup>(wire_, offsets);
  }
  std::unique_ptr<OutputLine> request_output(uint32_t offset, bool initial_high, std::string* error) override {
    if (offset >= line_count()) return *error = "line " + std::to_string(offset) + " is beyond the chip", nullptr;
    if (wire_->requested(offset)) return *error = "line " + std::to_string(offset) + " is busy", nullptr;
    auto out = std::make_unique<SimulatedOutput>(wire_, offset);
    out->set_level(initial_high);
    return out;
  }

 private:
  SimulatedGpio* wire_;
};

SimulatedGpio::SimulatedGpio(uint32_t line_count, size_t fifo_events)
    : levels_(line_count, 0), owner_(line_count, nullptr), output_(line_count, 0), fifo_events_(fifo_events) {}

SimulatedGpio::~SimulatedGpio() = default;

std::unique_ptr<GpioChip> SimulatedGpio::chip() { return std::make_unique<SimulatedChip>(this); }

void SimulatedGpio::set_level(uint32_t offset, bool high, uint64_t ts) {
  if (offset >= levels_.size() || output_[offset] != 0 || (levels_[offset] != 0) == high) return;
  levels_[offset] = high ? 1 : 0;
  if (owner_[offset] != nullptr)
    owner_[offset]->queue(offset, LineEvent{offset, high ? Edge::kRising : Edge::kFalling, ts});
}

void SimulatedGpio::inject_edge(uint32_t offset, Edge edge, uint64_t ts) {
  if (offset >= levels_.size() || output_[offset] != 0) return;
  levels_[offset] = edge == Edge::kRising ? 1 : 0;
  if (owner_[offset] != nullptr) owner_[offset]->queue(offset, LineEvent{offset, edge, ts});
}

}  // namespace sinew::hal::gpio
