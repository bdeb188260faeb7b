// The simulated rig's encoders read back through GpioSource on the simulated
// chip: the decoded angle equals the motion's count at every tick (exactly,
// not within a tolerance), index homing waits for the zero mark, glitches are
// counted without moving the count, and ticks allocate nothing.
#include "hal/gpio/sim/simulated_encoders.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>

#include "hal/common/input_health.hpp"
#include "hal/gpio/gpio_source.hpp"
#include "hal/gpio/quadrature.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/time_units.hpp"

namespace sinew::hal::sim {
namespace {

using hal::gpio::EncoderConfig;

using sinew::test::kMs;
constexpr uint64_t kStart = 5'000 * kMs;  // any monotonic start

int32_t deg(double d) { return static_cast<int32_t>(static_cast<int64_t>(d / 360.0 * 4294967296.0)); }

// Three rotational inputs: a symmetric range, an elbow-like 0..150 and one more.
std::vector<InputRange> ranges() { return {{deg(-100), deg(100)}, {deg(0), deg(150)}, {deg(-70), deg(80)}}; }

EncoderConfig encoder(uint16_t input, uint32_t a, uint32_t b, uint32_t cpt) {
  EncoderConfig e;
  e.input = input;
  e.line_a = a;
  e.line_b = b;
  e.counts_per_turn = cpt;
  return e;
}

struct Rig {
  std::unique_ptr<SimulatedEncoders> encoders;
  std::unique_ptr<hal::gpio::GpioSource> source;
  hal::InputHealth health;
  std::array<hal::JointSample, 8> out{};

  Rig(std::vector<EncoderConfig> config, SimulatedEncoderOptions options = {}) {
    const std::vector<bool> rotation(3, true);
    const RigMotion motion(ranges());
    std::string error;
    EXPECT_TRUE(SimulatedEncoders::validate(config, options, motion, rotation, 16, &error)) << error;
    encoders = std::make_unique<SimulatedEncoders>(motion, config, options, 16, kStart);
    hal::gpio::GpioSourceConfig c;
    c.name = "sim-encoders";
    c.encoders = config;
    source = hal::gpio::GpioSource::create(c, encoders->wire().chip(), &error);
    EXPECT_TRUE(source) << error;
    const hal::InputLimits limits[3] = {};
    const int32_t initial[3] = {};
    health.init(limits, initial, kStart);
  }
  // One tick at t after the start; returns the number of samples in `out`.
  size_t tick(uint64_t t) {
    encoders->advance(kStart + t);
    return source->latch(kStart + t, out, health);
  }
  const hal::JointSample* sample(size_t n, uint16_t input) const {
    for (size_t i = 0; i < n; ++i)
      if (out[i].input == input) return &out[i];
    return nullptr;
  }
};

TEST(SimulatedEncoders, DecodedAngleIsTheMotionsCountAtEveryTick) {
  // Input 0 starts at 0 deg (its range's centre), where count 0 is: no homing needed.
  std::vector<EncoderConfig> config = {encoder(0, 0, 1, 4096)};
  config.push_back(encoder(2, 2, 3, 10000));
  config[1].invert = true;
  config[1].active_low = true;
  config[1].offset = deg(5);  // input 2 starts at 5 deg, the centre of -70..80
  Rig rig(config);
  ASSERT_EQ(rig.encoders->position(1), 0);
  int64_t lowest = 0, highest = 0;
  for (uint64_t t = kMs; t <= 4000 * kMs; t += kMs) {
    const size_t n = rig.tick(t);
    ASSERT_EQ(n, 2u);
    for (size_t e = 0; e < 2; ++e) {
      const int64_t expected = rig.encoders->target_count(e, t);
      const hal::JointSample* s = rig.sample(n, config[e].input);
      ASSERT_NE(s, nullptr);
      ASSERT_EQ(s->value, hal::gpio::counts_to_angle(expected, config[e].counts_per_turn, config[e].offset))
          << "encoder " << e << " at " << t / kMs << " ms";
      lowest = std::min(lowest, expected);
      highest = std::max(highest, expected);
    }
  }
  // The swings really went both ways over most of their ranges.
  EXPECT_LT(lowest, -1000);
  EXPECT_GT(highest, 1000);
  EXPECT_EQ(rig.source->counters().late_events, 0u);
  EXPECT_EQ(rig.source->encoder(0).counters().illegal, 0u);
  EXPECT_EQ(rig.source->encoder(0).counters().missed_edges, 0u);
  EXPECT_EQ(rig.source->state(), hal::SourceState::kOk);
  std::printf("encoder 0: counts %lld..%lld, %llu edges decoded\n", static_cast<long long>(lowest),
              static_cast<long long>(highest), static_cast<unsigned long long>(rig.source->counters().events));
}

TEST(SimulatedEncoders, WithoutHomingTheAngleIsOffByThePowerUpPose) {
  // Input 1 powers up at 75 deg, but the config claims 0 deg: a relative
  // encoder cannot know; the error stays constant.
  Rig rig({encoder(1, 0, 1, 3600)});
  const int64_t start = rig.encoders->target_count(0, 0);
  ASSERT_EQ(start, 750);
  for (uint64_t t = kMs; t <= 500 * kMs; t += kMs) {
    const size_t n = rig.tick(t);
    ASSERT_EQ(n, 1u);
    ASSERT_EQ(rig.out[0].value, hal::gpio::counts_to_angle(rig.encoders->target_count(0, t) - start, 3600, 0));
  }
}

TEST(SimulatedEncoders, IndexLineHomesAtTheZeroMark) {
  // Input 1 (0..150 deg) with its zero mark at 75 deg, where it powers up: the
  // first pulse comes when the swing returns there, half its 2.37 s period later.
  std::vector<EncoderConfig> config = {encoder(1, 4, 5, 3600)};
  config[0].line_index = 6;
  config[0].offset = deg(75);
  Rig rig(config);
  uint64_t homed_at = 0;
  for (uint64_t t = kMs; t <= 3200 * kMs; t += kMs) {
    const size_t n = rig.tick(t);
    if (homed_at == 0 && n == 0) continue;  // not homed: no sample at all
    if (homed_at == 0) homed_at = t;
    ASSERT_EQ(n, 1u);
    ASSERT_EQ(rig.out[0].value, hal::gpio::counts_to_angle(rig.encoders->target_count(0, t), 3600, deg(75)))
        << t / kMs << " ms";
  }
  std::printf("homed at %llu ms, %llu index pulses\n", static_cast<unsigned long long>(homed_at / kMs),
              static_cast<unsigned long long>(rig.encoders->index_pulses()));
  EXPECT_GT(homed_at, 1150 * kMs);
  EXPECT_LT(homed_at, 1200 * kMs);
  EXPECT_GE(rig.encoders->index_pulses(), 2u);
  EXPECT_TRUE(rig.source->encoder(0).homed());
  EXPECT_EQ(rig.source->encoder(0).counters().index_corrections, 0u) << "every later pulse found the count right";
}

TEST(SimulatedEncoders, GlitchesAreCountedAndNeverMoveTheCount) {
  SimulatedEncoderOptions options;
  options.faults.faults.push_back(Fault{FaultKind::kEncoderGlitch, 1000 * kMs, 1200 * kMs, 0, 0});
  Rig rig({encoder(0, 0, 1, 4096), encoder(2, 2, 3, 4096)}, options);
  bool degraded_in_window = false;
  for (uint64_t t = kMs; t <= 2000 * kMs; t += kMs) {
    const size_t n = rig.tick(t);
    ASSERT_EQ(n, 2u);
    const hal::JointSample* s = rig.sample(n, 0);
    ASSERT_EQ(s->value, hal::gpio::counts_to_angle(rig.encoders->target_count(0, t), 4096, 0)) << t / kMs << " ms";
    if (t > 1000 * kMs && t <= 1200 * kMs) degraded_in_window |= rig.source->state() == hal::SourceState::kDegraded;
  }
  EXPECT_EQ(rig.encoders->glitches(), 200u);
  EXPECT_EQ(rig.source->encoder(0).counters().illegal, 400u) << "each glitch: out and back, both illegal";
  EXPECT_EQ(rig.source->encoder(1).counters().illegal, 0u) << "the other input's encoder was not hit";
  EXPECT_TRUE(degraded_in_window);
  EXPECT_EQ(rig.source->state(), hal::SourceState::kOk) << "recovers after the window";
}

TEST(SimulatedEncoders, RejectsBadWiring) {
  const RigMotion motion(ranges());
  std::string error;
  const std::vector<bool> rotation = {true, false, true};
  EXPECT_FALSE(SimulatedEncoders::validate({encoder(1, 0, 1, 4096)}, {}, motion, rotation, 16, &error));
  EXPECT_NE(error.find("translational"), std::string::npos) << error;
  const std::vector<bool> all(3, true);
  EXPECT_FALSE(SimulatedEncoders::validate({encoder(0, 0, 16, 4096)}, {}, motion, all, 16, &error));
  EXPECT_NE(error.find("line 16 is beyond"), std::string::npos) << error;
  EXPECT_FALSE(SimulatedEncoders::validate({encoder(0, 0, 1, 64), encoder(2, 1, 2, 64)}, {}, motion, all, 16, &error));
  EXPECT_NE(error.find("line 1 is used twice"), std::string::npos) << error;
  EXPECT_FALSE(SimulatedEncoders::validate({encoder(7, 0, 1, 64)}, {}, motion, all, 16, &error));
  EXPECT_NE(error.find("no rig input"), std::string::npos) << error;
  SimulatedEncoderOptions fast;
  fast.update_ns = 1000;
  EXPECT_FALSE(SimulatedEncoders::validate({encoder(0, 0, 1, 64)}, fast, motion, all, 16, &error));
  EXPECT_NE(error.find("update period"), std::string::npos) << error;
}

TEST(SimulatedEncoders, TicksNeverTouchTheHeap) {
  SimulatedEncoderOptions options;
  options.faults.faults.push_back(Fault{FaultKind::kEncoderGlitch, 100 * kMs, 300 * kMs, -1, 0});
  std::vector<EncoderConfig> config = {encoder(0, 0, 1, 4096), encoder(1, 2, 3, 4096)};
  config[1].line_index = 4;
  Rig rig(config, options);
  rig.tick(kMs);
  const uint64_t before = test::allocation_count();
  for (uint64_t t = 2 * kMs; t <= 5000 * kMs; t += kMs) rig.tick(t);
  EXPECT_EQ(test::allocation_count() - before, 0u);
}

}  // namespace
}  // namespace sinew::hal::sim
