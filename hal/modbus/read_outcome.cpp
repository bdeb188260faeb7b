#include "read_outcome.hpp"

#include <modbus.h>

#include <cerrno>

namespace sinew::hal::modbus {

ReadResult classify_error(int error) {
  ReadResult r;
  r.error = error;
  if (error > MODBUS_ENOBASE && error < MODBUS_ENOBASE + MODBUS_EXCEPTION_MAX) {
    r.outcome = ReadOutcome::kException;
    r.exception_code = static_cast<uint8_t>(error - MODBUS_ENOBASE);
    return r;
  }
  switch (error) {
    case ETIMEDOUT:
      r.outcome = ReadOutcome::kTimeout;
      break;
    case EMBBADCRC:
    case EMBBADDATA:
    case EMBBADEXC:
    case EMBUNKEXC:
    case EMBMDATA:
    case EMBBADSLAVE:
      r.outcome = ReadOutcome::kBadResponse;
      break;
    default:
      r.outcome = ReadOutcome::kLinkLost;
      break;
  }
  return r;
}

const char* outcome_name(ReadOutcome o) {
  switch (o) {
    case ReadOutcome::kOk:
      return "ok";
    case ReadOutcome::kException:
      return "exception";
    case ReadOutcome::kTimeout:
      return "timeout";
    case ReadOutcome::kBadResponse:
      return "bad response";
    case ReadOutcome::kLinkLost:
      return "link lost";
  }
  return "unknown";
}

const char* exception_name(uint8_t code) {
  switch (code) {
    case 0:
      return "none";
    case MODBUS_EXCEPTION_ILLEGAL_FUNCTION:
      return "illegal function";
    case MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS:
      return "illegal data address";
    case MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE:
      return "illegal data value";
    case MODBUS_EXCEPTION_SLAVE_OR_SERVER_FAILURE:
      return "server device failure";
    case MODBUS_EXCEPTION_ACKNOWLEDGE:
      return "acknowledge";
    case MODBUS_EXCEPTION_SLAVE_OR_SERVER_BUSY:
      return "server device busy";
    case MODBUS_EXCEPTION_NEGATIVE_ACKNOWLEDGE:
      return "negative acknowledge";
    case MODBUS_EXCEPTION_MEMORY_PARITY:
      return "memory parity error";
    case MODBUS_EXCEPTION_GATEWAY_PATH:
      return "gateway path unavailable";
    case MODBUS_EXCEPTION_GATEWAY_TARGET:
      return "gateway target failed to respond";
    default:
      return "undefined exception";
  }
}

}  // namespace sinew::hal::modbus
