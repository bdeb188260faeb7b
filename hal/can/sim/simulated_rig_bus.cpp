#include "hal/can/sim/simulated_rig_bus.hpp"

#include "hal/can/joint_record.hpp"
#include "hal/can/joint_stream_encoder.hpp"

namespace sinew::hal::sim {

using hal::can::CanFrame;

bool SimulatedRigBus::validate(const SimulatedRigOptions& o, size_t inputs, std::string* error) {
  if (o.period_ns == 0 || o.period_ns % 1000 != 0)
    return *error = "simulated rig: period must be a positive whole number of microseconds", false;
  if (o.offset_ns % 1000 != 0) return *error = "simulated rig: offset must be whole microseconds", false;
  if (o.send_sync && (o.sync_id > hal::can::kStandardIdMask || (o.sync_id >= 0x100 && o.sync_id < 0x100 + inputs)))
    return *error =
               "simulated rig: the sync identifier must be 11-bit and not one of the joint frames' (0x100 + input)",
           false;
  if (inputs == 0 || inputs > hal::can::kDefaultMaxJoints)
    return *error = "simulated rig: 1.." + std::to_string(hal::can::kDefaultMaxJoints) + " inputs", false;
  for (const Fault& f : o.faults.faults) {
    if (f.to_ns <= f.from_ns)
      return *error = std::string("simulated rig: fault ") + fault_kind_name(f.kind) + " ends before it starts", false;
    if (f.input >= static_cast<int32_t>(inputs))
      return *error = std::string("simulated rig: fault ") + fault_kind_name(f.kind) + " names input " +
                      std::to_string(f.input) + " beyond the rig's " + std::to_string(inputs),
             false;
  }
  return true;
}

SimulatedRigBus::SimulatedRigBus(RigMotion motion, SimulatedRigOptions options, uint64_t start_ns)
    : motion_(std::move(motion)),
      options_(std::move(options)),
      stream_(hal::can::default_joint_stream_config(motion_.input_count(), false, options_.period_ns)),
      bus_(options_.queue_frames),
      start_ns_(start_ns),
      counters_(motion_.input_count(), 0) {}

void SimulatedRigBus::send_step(uint64_t t) {
  const uint64_t at = start_ns_ + t;
  const bool bus_off = options_.faults.active(FaultKind::kBusOff, t, -1) != nullptr;
  if (bus_off && !bus_off_) bus_.bus_off(at);
  if (!bus_off && bus_off_) bus_.restart(at);
  bus_off_ = bus_off;
  for (size_t i = 0; i < motion_.input_count(); ++i) {
    const auto input = static_cast<int32_t>(i);
    const hal::can::JointFrame& jf = stream_.frames[i];
    hal::can::JointRecord record;
    record.value = motion_.value(i, t);
    if (options_.faults.active(FaultKind::kOutOfRange, t, input)) {
      const InputRange& r = motion_.range(i);
      const int64_t far = int64_t{r.max} + (int64_t{r.max} - r.min) / 2 + (int64_t{1} << 27);
      record.value = static_cast<int32_t>(far > INT32_MAX ? INT32_MAX : far);
    }
    if (!options_.faults.active(FaultKind::kStuckCounter, t, input))
      counters_[i] = static_cast<uint8_t>((counters_[i] + 1) % hal::can::kAliveCounterModulo);
    record.counter = counters_[i];
    if (options_.faults.active(FaultKind::kDrop, t, input)) continue;
    CanFrame frame = hal::can::encode_classic_joint_frame(jf.can_id, jf.extended, jf.joints[0].data_id, record);
    frame.timestamp_ns = at;
    if (const Fault* d = options_.faults.active(FaultKind::kDelay, t, input)) frame.timestamp_ns += d->amount;
    if (options_.faults.active(FaultKind::kCorrupt, t, input)) frame.data[3] ^= 0x10;
    bus_.inject(frame);
    ++sent_;
    if (options_.faults.active(FaultKind::kDuplicate, t, input)) {
      bus_.inject(frame);
      ++sent_;
    }
  }
  if (options_.send_sync && !bus_off) {
    CanFrame sync = hal::can::make_data_frame(options_.sync_id, false, nullptr, 0);
    sync.timestamp_ns = at;
    bus_.inject(sync);
  }
}

size_t SimulatedRigBus::drain(std::span<CanFrame> out, uint64_t now_ns) {
  // Bounded catch-up: at most 1000 send steps per call (a drain called after
  // a long pause sends the backlog over several ticks, as a queue would).
  for (int steps = 0; steps < 1000; ++steps) {
    const uint64_t t = options_.offset_ns + next_step_ * options_.period_ns;
    if (start_ns_ + t > now_ns) break;
    send_step(t);
    ++next_step_;
  }
  return bus_.drain(out, now_ns);
}

}  // namespace sinew::hal::sim
