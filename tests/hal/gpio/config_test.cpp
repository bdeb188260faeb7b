// Bad configurations are rejected with a message naming the problem.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "hal/gpio/gpio_source.hpp"
#include "hal/gpio/simulated_gpio.hpp"

namespace sinew::hal::gpio {
namespace {

GpioSourceConfig valid() {
  GpioSourceConfig c;
  c.name = "arm-gpio";
  c.encoders.resize(1);
  c.encoders[0].line_a = 0;
  c.encoders[0].line_b = 1;
  c.limits.resize(1);
  c.limits[0].line = 2;
  return c;
}

struct Case {
  const char* what;
  std::function<void(GpioSourceConfig&)> edit;
  const char* expect;  // substring of the message
};

TEST(GpioSourceConfig, BadConfigsRejectedWithMessages) {
  const Case cases[] = {
      {"nothing configured", [](GpioSourceConfig& c) { c.encoders.clear(), c.limits.clear(); },
       "no encoders, limits, sync or fault line"},
      {"empty chip", [](GpioSourceConfig& c) { c.chip.clear(); }, "chip is empty"},
      {"long consumer", [](GpioSourceConfig& c) { c.consumer = std::string(40, 'x'); }, "consumer must be"},
      {"tiny event buffer", [](GpioSourceConfig& c) { c.event_capacity = 4; }, "event_capacity must be 16..65536"},
      {"zero counts", [](GpioSourceConfig& c) { c.encoders[0].counts_per_turn = 0; },
       "encoder 0: counts_per_turn must be 1..2^30"},
      {"too many counts", [](GpioSourceConfig& c) { c.encoders[0].counts_per_turn = (1u << 30) + 1; },
       "counts_per_turn"},
      {"window too long", [](GpioSourceConfig& c) { c.encoders[0].window_ns = 2'000'000; }, "window_ns"},
      {"A equals B", [](GpioSourceConfig& c) { c.encoders[0].line_b = 0; },
       "encoder 0 B line 0 is already used by encoder 0 A"},
      {"limit on an encoder line", [](GpioSourceConfig& c) { c.limits[0].line = 1; },
       "limit 0 line 1 is already used by encoder 0 B"},
      {"index beyond the chip", [](GpioSourceConfig& c) { c.encoders[0].line_index = 99; },
       "encoder 0 index line 99 is beyond the chip's 16 lines"},
      {"negative sync line", [](GpioSourceConfig& c) { c.sync.line = -5; }, "sync line must be >= 0"},
      {"fault on the sync line", [](GpioSourceConfig& c) { c.sync.line = 7, c.fault.line = 7; },
       "fault line 7 is already used by sync"},
      {"two encoders one input",
       [](GpioSourceConfig& c) {
         c.encoders.push_back(c.encoders[0]);
         c.encoders[1].line_a = 5;
         c.encoders[1].line_b = 6;
       },
       "encoder 1: input 0 is fed by two encoders"},
      {"debounce too long", [](GpioSourceConfig& c) { c.limits[0].debounce_ns = 2'000'000'000; },
       "limit 0: debounce_ns must be at most 1 s"},
      {"two min limits", [](GpioSourceConfig& c) { c.limits.push_back(c.limits[0]), c.limits[1].line = 3; },
       "limit 1: input 0 already has a min limit switch"},
  };
  for (const Case& k : cases) {
    GpioSourceConfig c = valid();
    k.edit(c);
    SimulatedGpio wire(16);
    std::string error;
    EXPECT_EQ(GpioSource::create(c, wire.chip(), &error), nullptr) << k.what;
    EXPECT_NE(error.find(k.expect), std::string::npos) << k.what << ": " << error;
    EXPECT_NE(error.find("gpio source 'arm-gpio'"), std::string::npos) << error;
    std::printf("  %-26s -> %s\n", k.what, error.c_str());
  }
  SimulatedGpio wire(16);
  std::string error;
  EXPECT_NE(GpioSource::create(valid(), wire.chip(), &error), nullptr) << error;
}

TEST(GpioSourceConfig, BusyLineRefusedByTheChip) {
  SimulatedGpio wire(16);
  std::string error;
  auto first = GpioSource::create(valid(), wire.chip(), &error);
  ASSERT_TRUE(first) << error;
  EXPECT_EQ(GpioSource::create(valid(), wire.chip(), &error), nullptr);
  std::printf("second source on the same lines: %s\n", error.c_str());
  EXPECT_NE(error.find("line 0 is busy"), std::string::npos) << error;
}

TEST(GpioSourceConfig, MissingChipNamed) {
  GpioSourceConfig c = valid();
  c.chip = "sinew-no-such-chip";
  std::string error;
  EXPECT_EQ(GpioSource::create(c, &error), nullptr);
  std::printf("missing chip: %s\n", error.c_str());
  EXPECT_NE(error.find("gpio chip 'sinew-no-such-chip'"), std::string::npos) << error;
  EXPECT_EQ(GpioSource::create(valid(), nullptr, &error), nullptr);
  EXPECT_NE(error.find("no chip"), std::string::npos) << error;
}

}  // namespace
}  // namespace sinew::hal::gpio
