// What became of one Modbus request, from libmodbus's errno: data, an
// exception response (the device answered "no", with a code), no answer in
// time, a malformed answer, or a lost link.
#pragma once

#include <cstdint>

namespace sinew::hal::modbus {

enum class ReadOutcome : uint8_t {
  kOk,
  kException,    // exception response; see exception_code
  kTimeout,      // no (complete) response within the response timeout
  kBadResponse,  // CRC, transaction id, length or unit id mismatch
  kLinkLost,     // connection reset or closed, socket or serial I/O error
};

// Modbus exception codes 1..11 (0 = none); index of per-code counters.
inline constexpr int kExceptionCodes = 12;

struct ReadResult {
  ReadOutcome outcome = ReadOutcome::kOk;
  uint8_t exception_code = 0;  // kException only
  int error = 0;               // errno as libmodbus left it
};

// Classifies errno after a failed libmodbus call.
ReadResult classify_error(int error);

const char* outcome_name(ReadOutcome o);
const char* exception_name(uint8_t code);  // "illegal data address", "server device busy", ...

}  // namespace sinew::hal::modbus
