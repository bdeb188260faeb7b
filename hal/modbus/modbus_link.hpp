// One libmodbus client context (TCP or RTU), used by the poller thread only.
// Keeps <modbus.h> out of every other header. Error recovery stays at
// libmodbus's default "none": the poller decides when to reconnect, so no
// call can hide a multi-second reconnect loop.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "poller_config.hpp"
#include "read_outcome.hpp"
#include "register_channel.hpp"

struct _modbus;

namespace sinew::hal::modbus {

class ModbusLink {
 public:
  // Creates the context (no I/O yet). ok() is false if libmodbus refused the
  // parameters; error() says why.
  ModbusLink(const LinkConfig& link, uint64_t response_timeout_ns, uint64_t byte_timeout_ns);
  ~ModbusLink();
  ModbusLink(const ModbusLink&) = delete;
  ModbusLink& operator=(const ModbusLink&) = delete;

  bool ok() const { return ctx_ != nullptr; }
  const std::string& error() const { return error_; }

  // Opens the TCP connection (bounded by the response timeout) or the serial port.
  bool connect();
  void close();
  bool connected() const { return connected_; }
  // Reads `dest.size()` registers (1..125) starting at `address`.
  ReadResult read(RegisterTable table, uint16_t address, std::span<uint16_t> dest);
  // Discards whatever is pending on the link (a late or partial response).
  void flush();
  Transport transport() const { return transport_; }

 private:
  _modbus* ctx_ = nullptr;
  Transport transport_;
  bool rs485_ = false;
  bool connected_ = false;
  std::string error_;
};

}  // namespace sinew::hal::modbus
