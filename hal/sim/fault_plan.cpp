#include "hal/sim/fault_plan.hpp"

#include <array>
#include <utility>

namespace sinew::hal::sim {

namespace {

constexpr std::array<std::pair<FaultKind, const char*>, 10> kNames{{
    {FaultKind::kDrop, "drop"},
    {FaultKind::kDelay, "delay"},
    {FaultKind::kDuplicate, "duplicate"},
    {FaultKind::kCorrupt, "corrupt"},
    {FaultKind::kStuckCounter, "stuck-counter"},
    {FaultKind::kOutOfRange, "out-of-range"},
    {FaultKind::kBusOff, "bus-off"},
    {FaultKind::kModbusTimeout, "modbus-timeout"},
    {FaultKind::kModbusException, "modbus-exception"},
    {FaultKind::kEncoderGlitch, "encoder-glitch"},
}};

}  // namespace

const Fault* FaultPlan::active(FaultKind kind, uint64_t t_ns, int32_t input) const {
  for (const Fault& f : faults)
    if (f.kind == kind && t_ns >= f.from_ns && t_ns < f.to_ns && (f.input < 0 || f.input == input)) return &f;
  return nullptr;
}

const char* fault_kind_name(FaultKind kind) {
  for (const auto& [k, name] : kNames)
    if (k == kind) return name;
  return "unknown";
}

bool parse_fault_kind(const std::string& name, FaultKind* kind) {
  for (const auto& [k, n] : kNames)
    if (name == n) return *kind = k, true;
  return false;
}

}  // namespace sinew::hal::sim
