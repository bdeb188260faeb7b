// Configuration of one GPIO source: the chip, quadrature encoders (A/B and
// an optional index line), debounced limit switches, an optional external
// sync input and an optional status/fault output. Validated once at
// start-up; the TOML keys are listed in docs/gpio.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace sinew::hal::gpio {

inline constexpr int32_t kNoLine = -1;

struct EncoderConfig {
  uint16_t input = 0;   // rig input the angle feeds
  uint32_t line_a = 0;  // line offsets on the chip
  uint32_t line_b = 1;
  int32_t line_index = kNoLine;     // index (Z) line for homing, or kNoLine
  bool active_low = false;          // applies to A, B and index
  uint32_t counts_per_turn = 4096;  // 4x counts (4 per line period) per joint turn, 1 .. 2^30
  int32_t offset = 0;               // binary angle added to the decoded angle (2^32 = one turn)
  bool invert = false;              // count B-leads-A as forward
  uint64_t window_ns = 0;           // edges this close form one sample (illegal if both lines changed); <= 1 ms
  int64_t index_count = 0;          // count set by the index pulse (homing)
  bool home_every_index = false;    // re-home on every index pulse (counting corrections), not only the first
};

enum class LimitSide : uint8_t { kMin, kMax };

struct LimitSwitchConfig {
  uint16_t input = 0;  // rig input whose travel it limits
  uint32_t line = 0;
  bool active_low = true;  // contact to ground with a pull-up: pressed = low
  LimitSide side = LimitSide::kMin;
  uint64_t debounce_ns = 5'000'000;  // level must hold this long, 0 .. 1 s
};

struct SyncConfig {
  int32_t line = kNoLine;  // external sync input: its active edge starts a tick
  bool active_low = false;
};

struct FaultOutputConfig {
  int32_t line = kNoLine;   // status/fault output
  bool active_low = false;  // fault asserted = active level
};

struct GpioSourceConfig {
  std::string name = "gpio";       // the source's name in reports
  std::string chip = "gpiochip0";  // name, /dev path, number or label
  std::string consumer = "sinew";  // label shown by gpioinfo for the requested lines
  std::vector<EncoderConfig> encoders;
  std::vector<LimitSwitchConfig> limits;
  SyncConfig sync;
  FaultOutputConfig fault;
  uint32_t event_capacity = 1024;  // events staged between latches, 16 .. 65536
};

// Checks every field, that some line is configured, that no line is used
// twice and that no two encoders feed one input. line_count: lines of the
// chip (0 skips the range check). False with a message naming the offender.
bool validate(const GpioSourceConfig& config, uint32_t line_count, std::string* error);

}  // namespace sinew::hal::gpio
