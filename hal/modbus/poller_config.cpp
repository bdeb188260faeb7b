#include "poller_config.hpp"

#include <arpa/inet.h>

#include <set>

namespace sinew::hal::modbus {

namespace {

constexpr uint64_t kMaxTimeoutNs = 60'000'000'000;  // beyond this a device is simply down

bool validate_link(const LinkConfig& link, std::string* error) {
  if (link.transport == Transport::kTcp) {
    in_addr addr{};
    if (inet_pton(AF_INET, link.tcp.host.c_str(), &addr) != 1)
      return *error = "tcp host '" + link.tcp.host + "' is not an IPv4 address", false;
    if (link.tcp.port == 0) return *error = "tcp port must be 1..65535", false;
    if (link.unit_id > 247 && link.unit_id != 255) return *error = "tcp unit_id must be 0..247 or 255", false;
    return true;
  }
  const RtuEndpoint& rtu = link.rtu;
  if (rtu.device.empty()) return *error = "rtu device is empty", false;
  if (rtu.baud == 0) return *error = "rtu baud must be positive", false;
  if (rtu.parity != 'N' && rtu.parity != 'E' && rtu.parity != 'O')
    return *error = "rtu parity must be N, E or O", false;
  if (rtu.data_bits < 5 || rtu.data_bits > 8) return *error = "rtu data_bits must be 5..8", false;
  if (rtu.stop_bits != 1 && rtu.stop_bits != 2) return *error = "rtu stop_bits must be 1 or 2", false;
  if (link.unit_id < 1 || link.unit_id > 247) return *error = "rtu unit_id must be 1..247", false;
  return true;
}

}  // namespace

bool validate(const PollerConfig& config, std::string* error) {
  const std::string prefix = "modbus source '" + config.name + "': ";
  std::string why;
  if (!validate_link(config.link, &why)) return *error = prefix + why, false;
  if (config.channels.empty()) return *error = prefix + "no channels", false;
  if (config.channels.size() > 65535) return *error = prefix + "too many channels", false;
  if (config.response_timeout_ns < 1000 || config.response_timeout_ns > kMaxTimeoutNs)
    return *error = prefix + "response timeout must be 1 us .. 60 s", false;
  if (config.byte_timeout_ns > kMaxTimeoutNs) return *error = prefix + "byte timeout must be at most 60 s", false;
  if (config.backoff_initial_ns == 0 || config.backoff_max_ns < config.backoff_initial_ns)
    return *error = prefix + "back-off needs 0 < initial <= max", false;
  if (config.max_registers_per_read < 1 || config.max_registers_per_read > 125)
    return *error = prefix + "max_registers_per_read must be 1..125", false;
  std::set<uint16_t> inputs;
  for (const ChannelConfig& c : config.channels) {
    if (!validate(c, &why)) return *error = prefix + why, false;
    if (!inputs.insert(c.input).second)
      return *error = prefix + "input " + std::to_string(c.input) + " is fed by two channels", false;
  }
  return true;
}

}  // namespace sinew::hal::modbus
