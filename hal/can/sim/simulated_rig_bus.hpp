// The simulated rig on the in-process CAN bus: a frame source that, when
// drained at time `now`, first "sends" every frame the rig would have sent
// by then (one default joint-stream frame per input per period, timestamped
// on the rig's own schedule) through a SimulatedCanBus, with the fault plan
// applied, then drains that bus like a socket. Frames depend only on the
// schedule, never on when drain() is called: live, offline and replayed
// runs see the same frames. No allocation after construction.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hal/can/joint_stream_config.hpp"
#include "hal/can/simulated_can_bus.hpp"
#include "hal/sim/fault_plan.hpp"
#include "hal/sim/rig_motion.hpp"

namespace sinew::hal::sim {

struct SimulatedRigOptions {
  uint64_t period_ns = 10'000'000;  // send period per input; whole microseconds
  uint64_t offset_ns = 5'000'000;   // first frame at start + offset (half a period off the tick grid)
  FaultPlan faults;
  size_t queue_frames = 4096;  // the simulated socket's receive queue
  // A sync frame (no payload, classic, 11-bit) after each step's joint
  // frames, stamped with them: the cycle's end for a `trigger = "sync"` loop.
  bool send_sync = false;
  uint32_t sync_id = 0x080;
};

class SimulatedRigBus final : public hal::can::FrameSource {
 public:
  // The default joint-stream layout for the motion's inputs (classic CAN,
  // input i on 0x100 + i, data ID 0x5300 + i).
  static bool validate(const SimulatedRigOptions& options, size_t inputs, std::string* error);
  SimulatedRigBus(RigMotion motion, SimulatedRigOptions options, uint64_t start_ns);

  const char* name() const override { return "simulated-rig"; }
  bool set_filters(std::span<const hal::can::FrameId> ids, std::string* error) override {
    return bus_.set_filters(ids, error);
  }
  size_t drain(std::span<hal::can::CanFrame> out, uint64_t now_ns) override;
  hal::can::BusState bus_state() const override { return bus_.bus_state(); }
  const hal::can::BusCounters& counters() const override { return bus_.counters(); }

  // The protocol configuration the receiving side must use.
  const hal::can::JointStreamConfig& stream_config() const { return stream_; }
  uint64_t frames_sent() const { return sent_; }

 private:
  void send_step(uint64_t t_ns);

  RigMotion motion_;
  SimulatedRigOptions options_;
  hal::can::JointStreamConfig stream_;
  hal::can::SimulatedCanBus bus_;
  uint64_t start_ns_;
  uint64_t next_step_ = 0;         // index of the next send step
  std::vector<uint8_t> counters_;  // alive counter per input
  bool bus_off_ = false;
  uint64_t sent_ = 0;
};

}  // namespace sinew::hal::sim
