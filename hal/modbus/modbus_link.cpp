#include "modbus_link.hpp"

#include <modbus.h>

#include <cerrno>

namespace sinew::hal::modbus {

namespace {

uint32_t whole_seconds(uint64_t ns) { return static_cast<uint32_t>(ns / 1'000'000'000u); }
uint32_t remaining_us(uint64_t ns) { return static_cast<uint32_t>(ns % 1'000'000'000u / 1000u); }

std::string describe(const char* what) { return std::string(what) + ": " + modbus_strerror(errno); }

}  // namespace

ModbusLink::ModbusLink(const LinkConfig& link, uint64_t response_timeout_ns, uint64_t byte_timeout_ns)
    : transport_(link.transport), rs485_(link.rtu.rs485) {
  if (link.transport == Transport::kTcp) {
    ctx_ = modbus_new_tcp(link.tcp.host.c_str(), link.tcp.port);
  } else {
    ctx_ = modbus_new_rtu(link.rtu.device.c_str(), static_cast<int>(link.rtu.baud), link.rtu.parity, link.rtu.data_bits,
                          link.rtu.stop_bits);
  }
  if (ctx_ == nullptr) {
    error_ = describe("creating the libmodbus context");
    return;
  }
  // Never MODBUS_ERROR_RECOVERY_LINK: it reconnects inside read calls and can
  // block for seconds. Reconnects are the poller's, with back-off.
  bool ok = modbus_set_error_recovery(ctx_, MODBUS_ERROR_RECOVERY_NONE) == 0;
  ok = ok && modbus_set_slave(ctx_, link.unit_id) == 0;
  ok = ok &&
       modbus_set_response_timeout(ctx_, whole_seconds(response_timeout_ns), remaining_us(response_timeout_ns)) == 0;
  // Zero disables the byte timeout: the whole response must then arrive
  // within the response timeout, which bounds every request.
  ok = ok && modbus_set_byte_timeout(ctx_, whole_seconds(byte_timeout_ns), remaining_us(byte_timeout_ns)) == 0;
  if (!ok) {
    error_ = describe("configuring the libmodbus context");
    modbus_free(ctx_);
    ctx_ = nullptr;
  }
}

ModbusLink::~ModbusLink() {
  if (ctx_ == nullptr) return;
  close();
  modbus_free(ctx_);
}

bool ModbusLink::connect() {
  if (connected_) return true;
  if (modbus_connect(ctx_) != 0) {
    error_ = describe("connect");
    return false;
  }
  connected_ = true;
  if (transport_ == Transport::kRtu && rs485_ && modbus_rtu_set_serial_mode(ctx_, MODBUS_RTU_RS485) != 0) {
    error_ = describe("RS-485 mode");
    close();
    return false;
  }
  return true;
}

void ModbusLink::close() {
  if (!connected_) return;
  modbus_close(ctx_);
  connected_ = false;
}

ReadResult ModbusLink::read(RegisterTable table, uint16_t address, std::span<uint16_t> dest) {
  const int count = static_cast<int>(dest.size());
  const int rc = table == RegisterTable::kHolding ? modbus_read_registers(ctx_, address, count, dest.data())
                                                  : modbus_read_input_registers(ctx_, address, count, dest.data());
  if (rc == count) return ReadResult{};
  if (rc >= 0) return ReadResult{ReadOutcome::kBadResponse, 0, EMBBADDATA};
  return classify_error(errno);
}

void ModbusLink::flush() {
  if (connected_) modbus_flush(ctx_);
}

}  // namespace sinew::hal::modbus
