#include "hal/modbus/sim/modbus_feeder.hpp"

#include "hal/common/monotonic_clock.hpp"

namespace sinew::hal::sim {

bool ModbusFeeder::start(RigMotion motion, std::vector<bool> rotation, FaultPlan faults, uint64_t start_ns,
                         uint16_t port, std::string* error) {
  if (motion.input_count() * 2 > static_cast<size_t>(ModbusServer::kRegisters))
    return *error = "simulated Modbus device: too many inputs for its registers", false;
  motion_ = std::move(motion);
  rotation_ = std::move(rotation);
  faults_ = std::move(faults);
  start_ns_ = start_ns;
  update(hal::monotonic_ns());
  // Measured on demand: the server thread samples the motion and the faults
  // at each request, so a request never reads a value older than itself.
  server_.set_sampler([this](uint64_t now_ns) { update(now_ns); });
  if (!server_.start(port)) return *error = "simulated Modbus device: cannot listen on 127.0.0.1", false;
  return true;
}

void ModbusFeeder::update(uint64_t now_ns) {
  const uint64_t t = now_ns > start_ns_ ? now_ns - start_ns_ : 0;
  for (size_t i = 0; i < motion_.input_count(); ++i) {
    const int64_t v = motion_.value(i, t);
    // Angle: binary angle → 0.01 degree; length: Q12.20 → micrometre (rig unit = 1 m).
    const int64_t raw = rotation_[i] ? (v * 36000) / (int64_t{1} << 32) : (v * 1000000) / (int64_t{1} << 20);
    server_.set_holding32(static_cast<uint16_t>(2 * i), static_cast<uint32_t>(raw), true);
  }
  server_.set_mute(faults_.active(FaultKind::kModbusTimeout, t, -1) != nullptr);
  server_.fail_reads_at(faults_.active(FaultKind::kModbusException, t, -1) ? 0 : -1, 4);
}

}  // namespace sinew::hal::sim
