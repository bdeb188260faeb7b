// Configuration of one Modbus client source: the link (TCP or RTU), the
// mapped channels, the poll period, the response timeout and the back-off
// applied while the device does not answer. Validated once at start-up.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "register_channel.hpp"

namespace sinew::hal::modbus {

enum class Transport : uint8_t { kTcp, kRtu };

struct TcpEndpoint {
  std::string host = "127.0.0.1";  // IPv4 address (no name resolution on the poll path)
  uint16_t port = 502;
};

struct RtuEndpoint {
  std::string device;  // serial device, e.g. "/dev/ttyUSB0"
  uint32_t baud = 19200;
  char parity = 'E';      // 'N', 'E' or 'O'
  uint8_t data_bits = 8;  // 5..8
  uint8_t stop_bits = 1;  // 1 or 2
  bool rs485 = false;     // switch the port to RS-485 mode (TIOCSRS485)
};

struct LinkConfig {
  Transport transport = Transport::kTcp;
  TcpEndpoint tcp;
  RtuEndpoint rtu;
  // Unit identifier: RTU 1..247; TCP 0..247, or 255 (the TCP default, for
  // devices that ignore it).
  uint8_t unit_id = 1;
};

struct PollerConfig {
  std::string name = "modbus";  // the source's name in reports
  LinkConfig link;
  std::vector<ChannelConfig> channels;
  uint64_t period_ns = 10'000'000;             // one poll cycle (all requests) every period; 0 = back to back
  uint64_t response_timeout_ns = 100'000'000;  // per request, and per TCP connect (libmodbus default: 500 ms)
  uint64_t byte_timeout_ns = 0;  // between bytes of a response; 0 = whole response within the response timeout
  uint64_t backoff_initial_ns = 50'000'000;  // first wait after a failed cycle or connect
  uint64_t backoff_max_ns = 2'000'000'000;   // the wait doubles up to this
  uint16_t max_registers_per_read = 125;     // 1..125 (some devices accept fewer)
  uint16_t max_gap = 0;                      // unmapped registers a request may read across
};

// Checks the link, timeouts, back-off, every channel, and that no two
// channels feed the same input. False with a message naming the offender.
bool validate(const PollerConfig& config, std::string* error);

}  // namespace sinew::hal::modbus
