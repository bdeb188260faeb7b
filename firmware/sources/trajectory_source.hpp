// The simulated twin of a live rig, inside the daemon: every input sweeps its
// joint's range (5 degrees past each limit, so clamping is exercised) along
// the shared deterministic sweep (hal/sim/sweep.hpp), and is "received" once
// per period, timestamped on that period's grid. Integer math only: identical
// everywhere.
#pragma once

#include <cstdint>
#include <vector>

#include "firmware/runtime/io.hpp"

namespace sinew::firmware {

class TrajectorySource : public InputSource {
 public:
  // min/max: each input's joint limits (engine units).
  TrajectorySource(std::vector<int32_t> min, std::vector<int32_t> max, uint64_t period_ns, uint64_t start_ns);
  // The value of input i at sample index k.
  int32_t value(uint32_t input, uint32_t k) const;
  const char* name() const override { return "trajectory"; }
  size_t latch(uint64_t until_ns, std::span<hal::JointSample> out, InputHealth& health) override;
  SourceState state() const override { return SourceState::kOk; }
  std::string status_line() const override;
  // Complete once a sample set is due (every input is sent at each grid point).
  uint8_t arrival_signals() const override { return hal::kSignalsComplete; }
  hal::Arrival arrival(uint64_t now_ns) override { return {next_ <= now_ns, false}; }

 private:
  std::vector<int32_t> centre_, half_span_;
  uint32_t inputs_;
  uint64_t period_;
  uint64_t next_;
  uint64_t start_;
  uint64_t sent_ = 0;
};

}  // namespace sinew::firmware
