#include "sources.hpp"

#include "bus_sources.hpp"
#include "dds_endpoints.hpp"
#include "firmware/sources/trajectory_source.hpp"

namespace sinew::firmware {
namespace {

constexpr ConfigKey kFaultKeys[] = {{"kind", KeyKind::kString},
                                    {"from_s", KeyKind::kNumber, 0, 1e6},
                                    {"to_s", KeyKind::kNumber, 0, 1e6},
                                    {"input", KeyKind::kString},
                                    {"delay_ms", KeyKind::kNumber, 0, kMaxMs}};
constexpr ConfigKey kChannelKeys[] = {{"input", KeyKind::kString},
                                      {"table", KeyKind::kString},
                                      {"address", KeyKind::kInteger, 0, 65535},
                                      {"width", KeyKind::kInteger, 16, 32},
                                      {"word_order", KeyKind::kString},
                                      {"signed", KeyKind::kFlag},
                                      {"scale", KeyKind::kNumber, -1e12, 1e12},
                                      {"offset", KeyKind::kNumber, -1e12, 1e12},
                                      {"quantity", KeyKind::kString},
                                      {"min", KeyKind::kNumber, -1e12, 1e12},
                                      {"max", KeyKind::kNumber, -1e12, 1e12}};
constexpr ConfigKey kEncoderKeys[] = {{"input", KeyKind::kInput},
                                      {"line_a", KeyKind::kInteger, 0, 65535},
                                      {"line_b", KeyKind::kInteger, 0, 65535},
                                      {"line_index", KeyKind::kInteger, -1, 65535},
                                      {"active_low", KeyKind::kFlag},
                                      {"counts_per_turn", KeyKind::kInteger, 1, 1 << 30},
                                      {"offset_deg", KeyKind::kNumber, -360, 360},
                                      {"invert", KeyKind::kFlag},
                                      {"window_us", KeyKind::kNumber, 0, 1000},
                                      {"index_count", KeyKind::kInteger, -2147483648.0, 2147483647.0},
                                      {"home_every_index", KeyKind::kFlag}};
constexpr ConfigKey kLimitKeys[] = {{"input", KeyKind::kInput},
                                    {"line", KeyKind::kInteger, 0, 65535},
                                    {"active_low", KeyKind::kFlag},
                                    {"side", KeyKind::kString},
                                    {"debounce_ms", KeyKind::kNumber, 0, 1000}};
constexpr ConfigKey kLineKeys[] = {{"line", KeyKind::kInteger, -1, 65535}, {"active_low", KeyKind::kFlag}};

// Keys every CAN-fed source reads (can_source in bus_sources.cpp).
#define SINEW_CAN_KEYS                                                                                   \
  {"type", KeyKind::kString}, {"name", KeyKind::kString}, {"period_ms", KeyKind::kNumber, 0.01, kMaxMs}, \
      {"fd", KeyKind::kFlag}, {"record", KeyKind::kString}, {"interface", KeyKind::kString}, {           \
    "sync_id", KeyKind::kInteger, 0, 0x1FFFFFFF                                                          \
  }
constexpr ConfigKey kCanKeys[] = {SINEW_CAN_KEYS};
constexpr ConfigKey kCandumpKeys[] = {
    SINEW_CAN_KEYS, {"path", KeyKind::kString}, {"origin_s", KeyKind::kNumber, 0, 1e9}};
constexpr ConfigKey kSimulatedRigKeys[] = {SINEW_CAN_KEYS,
                                           {"offset_ms", KeyKind::kNumber, 0, kMaxMs},
                                           {"modbus_port", KeyKind::kInteger, 0, kMaxPort},
                                           {"fault", KeyKind::kTables, 0, 0, kFaultKeys}};
#undef SINEW_CAN_KEYS
constexpr ConfigKey kTrajectoryKeys[] = {
    {"type", KeyKind::kString}, {"name", KeyKind::kString}, {"period_ms", KeyKind::kNumber, 0.01, kMaxMs}};
constexpr ConfigKey kModbusKeys[] = {{"type", KeyKind::kString},
                                     {"name", KeyKind::kString},
                                     {"host", KeyKind::kString},
                                     {"port", KeyKind::kInteger, 1, kMaxPort},
                                     {"device", KeyKind::kString},
                                     {"baud", KeyKind::kInteger, 50, 4000000},
                                     {"unit_id", KeyKind::kInteger, 0, 255},
                                     {"period_ms", KeyKind::kNumber, 0, kMaxMs},
                                     {"timeout_ms", KeyKind::kNumber, 1, 10000},
                                     {"backoff_ms", KeyKind::kNumber, 1, kMaxMs},
                                     {"backoff_max_ms", KeyKind::kNumber, 1, 600000},
                                     {"layout", KeyKind::kString},
                                     {"channel", KeyKind::kTables, 0, 0, kChannelKeys}};
constexpr ConfigKey kGpioKeys[] = {{"type", KeyKind::kString},
                                   {"name", KeyKind::kString},
                                   {"chip", KeyKind::kString},
                                   {"consumer", KeyKind::kString},
                                   {"event_capacity", KeyKind::kInteger, 16, 65536},
                                   {"lines", KeyKind::kInteger, 1, 65536},
                                   {"update_ms", KeyKind::kNumber, 0.01, 1000},
                                   {"encoder", KeyKind::kTables, 0, 0, kEncoderKeys},
                                   {"limit", KeyKind::kTables, 0, 0, kLimitKeys},
                                   {"sync", KeyKind::kTable, 0, 0, kLineKeys},
                                   {"fault_line", KeyKind::kTable, 0, 0, kLineKeys},
                                   {"fault", KeyKind::kTables, 0, 0, kFaultKeys}};

constexpr ConfigKey kDdsJointKeys[] = {{"name", KeyKind::kString}, {"input", KeyKind::kInput}};
constexpr ConfigKey kDdsKeys[] = {{"type", KeyKind::kString},
                                  {"name", KeyKind::kString},
                                  {"domain_id", KeyKind::kInteger, 0, 232},
                                  {"namespace", KeyKind::kString},
                                  {"topic", KeyKind::kString},
                                  {"depth", KeyKind::kInteger, 1, 1000},
                                  {"joint", KeyKind::kTables, 0, 0, kDdsJointKeys}};

// The deterministic sweep of every rig input (hal/sim/sweep.hpp), for runs
// without hardware.
std::unique_ptr<hal::InputSource> open_trajectory(const SourceConfig& s, const SourceSetup& setup, std::string* error) {
  const double period_ms = s.table["period_ms"].value_or(setup.config.default_period_ms);
  // Below 10 us or beyond a minute the tick-count arithmetic would overflow or divide by zero.
  if (!(period_ms >= 0.01 && period_ms <= 60000))
    return *error = "source " + s.name + ": period_ms must be in [0.01, 60000]", nullptr;
  const rig::Rig& rig = setup.rig.rig;
  std::vector<int32_t> min(rig.input_count, 0), max(rig.input_count, 0);
  for (const rig::JointRecord& j : rig.joints)
    for (uint32_t d = 0; d < j.dof_count; ++d) {
      min[j.first_input + d] = j.dof_min[d];
      max[j.first_input + d] = j.dof_max[d];
    }
  return std::make_unique<TrajectorySource>(std::move(min), std::move(max), static_cast<uint64_t>(period_ms * 1e6),
                                            setup.start_ns);
}

constexpr SourceType kSourceTypes[] = {
    {"trajectory", kTrajectoryKeys, open_trajectory},
    {"can", kCanKeys, open_can_source},
    {"candump", kCandumpKeys, open_candump_source},
    {"simulated-rig", kSimulatedRigKeys, open_simulated_rig_source},
    {"modbus", kModbusKeys, open_modbus_source},
    {"gpio", kGpioKeys, open_gpio_source},
    {"dds", kDdsKeys, open_dds_source},
};

}  // namespace

std::span<const SourceType> source_types() { return kSourceTypes; }

std::unique_ptr<hal::InputSource> open_source(const SourceConfig& s, const SourceSetup& setup, std::string* error) {
  for (const SourceType& t : kSourceTypes)
    if (t.type == s.type) return t.open(s, setup, error);
  std::string known;
  for (const SourceType& t : kSourceTypes) known += (known.empty() ? "" : ", ") + std::string(t.type);
  return *error = "source " + s.name + ": unknown type '" + s.type + "' (" + known + ")", nullptr;
}

bool add_sources(const DaemonConfig& config, const LoadedRig& rig, uint64_t start_ns, Runtime* runtime,
                 std::string* error) {
  const SourceSetup setup{config, rig, start_ns};
  for (const SourceConfig& s : config.sources) {
    std::unique_ptr<hal::InputSource> source = open_source(s, setup, error);
    if (!source) return false;
    runtime->add_source(std::move(source));
  }
  return true;
}

}  // namespace sinew::firmware
