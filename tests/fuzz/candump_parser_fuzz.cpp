// libFuzzer target: any bytes as a candump log. The parser must never crash,
// read out of bounds or hang, and every line is either a frame, a comment or
// blank, or an error with a line number.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "hal/can/candump_format.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const sinew::hal::can::CandumpLog log = sinew::hal::can::parse_candump_log(text);
  for (const auto& f : log.frames) {
    if (!sinew::hal::can::is_well_formed(f.frame)) __builtin_trap();
    if (f.line == 0 || f.line > log.lines) __builtin_trap();
  }
  for (const auto& e : log.errors)
    if (e.line == 0 || e.line > log.lines || e.message.empty()) __builtin_trap();
  return 0;
}
