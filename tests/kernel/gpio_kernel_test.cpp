// The libgpiod backend against a real kernel's gpio-sim chip (inside the
// test VM of scripts/kernel-test.sh). Inputs are driven through gpio-sim's
// sysfs pull attributes, so the events come from the kernel's edge
// detection with its timestamps. Skips unless SINEW_GPIO_SIM_CHIP (chip
// name, e.g. gpiochip0) and SINEW_GPIO_SIM_SYSFS (the chip's sysfs folder
// holding sim_gpioN/) are set.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <time.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include "hal/common/input_health.hpp"
#include "hal/gpio/gpio_source.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/time_units.hpp"

namespace sinew::hal::gpio {
namespace {

using sinew::test::kMs;
constexpr uint8_t kForward[4] = {0, 2, 3, 1};  // AB Gray sequence

// Line map of the simulated chip (8 lines).
constexpr uint32_t kA = 0, kB = 1, kIndex = 2, kLimit = 3, kSync = 4, kFault = 5;

uint64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1'000'000'000u + static_cast<uint64_t>(ts.tv_nsec);
}

const char* env(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr && v[0] != '\0' ? v : nullptr;
}

// Writes a sysfs attribute with plain POSIX calls (stdio would allocate its
// FILE inside the allocation guard).
bool write_attr(const char* path, const char* value) {
  const int fd = ::open(path, O_WRONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const ssize_t len = static_cast<ssize_t>(std::strlen(value));
  const bool ok = ::write(fd, value, static_cast<size_t>(len)) == len;
  return ::close(fd) == 0 && ok;
}

class GpioSim : public ::testing::Test {
 protected:
  void SetUp() override {
    chip_ = env("SINEW_GPIO_SIM_CHIP");
    sysfs_ = env("SINEW_GPIO_SIM_SYSFS");
    if (chip_ == nullptr || sysfs_ == nullptr) GTEST_SKIP() << "no gpio-sim chip (run scripts/kernel-test.sh)";
    for (uint32_t line = 0; line < 5; ++line) pull(line, false);
    const hal::InputLimits limits[4] = {};
    const int32_t initial[4] = {};
    health_.init(limits, initial, 0);
  }
  void TearDown() override {
    source_.reset();
    if (sysfs_ != nullptr)
      for (uint32_t line = 0; line < 5; ++line) pull(line, false);
  }

  // Drives an input line's level through the simulator's pull.
  void pull(uint32_t line, bool high) {
    std::snprintf(path_, sizeof path_, "%s/sim_gpio%u/pull", sysfs_, line);
    ASSERT_TRUE(write_attr(path_, high ? "pull-up" : "pull-down")) << path_;
  }
  int value(uint32_t line) {
    std::snprintf(path_, sizeof path_, "%s/sim_gpio%u/value", sysfs_, line);
    FILE* f = std::fopen(path_, "r");
    int v = -1;
    if (f != nullptr) {
      if (std::fscanf(f, "%d", &v) != 1) v = -1;
      std::fclose(f);
    }
    return v;
  }

  GpioSourceConfig config() const {
    GpioSourceConfig c;
    c.name = "sim";
    c.chip = chip_;
    c.encoders.resize(1);
    c.encoders[0].input = 1;
    c.encoders[0].line_a = kA;
    c.encoders[0].line_b = kB;
    c.encoders[0].counts_per_turn = 400;
    return c;
  }
  void create(const GpioSourceConfig& c) {
    std::string error;
    source_ = GpioSource::create(c, &error);
    ASSERT_TRUE(source_) << error;
  }
  size_t latch() { return source_->latch(monotonic_ns(), out_, health_); }

  // Quarter-period steps through the pulls, latching every 4 steps (the v1 FIFO holds 16 events per line).
  void step(int steps) {
    for (int i = 0; i < (steps < 0 ? -steps : steps); ++i) {
      pos_ = (pos_ + (steps < 0 ? 3 : 1)) % 4;
      const uint8_t ab = kForward[pos_];
      const uint8_t prev = kForward[(pos_ + (steps < 0 ? 1 : 3)) % 4];
      if (((ab ^ prev) & 2) != 0) pull(kA, (ab & 2) != 0);
      if (((ab ^ prev) & 1) != 0) pull(kB, (ab & 1) != 0);
      if (i % 4 == 3) latch();
    }
    latch();
  }

  const char* chip_ = nullptr;
  const char* sysfs_ = nullptr;
  char path_[512] = {};
  int pos_ = 0;
  std::unique_ptr<GpioSource> source_;
  hal::InputHealth health_;
  std::array<JointSample, 4> out_{};
};

TEST_F(GpioSim, EncoderCountsBothWaysWithKernelTimestamps) {
  create(config());
  const uint64_t before = monotonic_ns();
  step(300);
  ASSERT_EQ(latch(), 1u);
  EXPECT_EQ(source_->encoder(0).count(), 300);
  step(-220);
  const uint64_t after = monotonic_ns();
  ASSERT_EQ(latch(), 1u);
  const QuadratureCounters& c = source_->encoder(0).counters();
  std::printf(
      "gpio-sim encoder: +300 -220 -> count %lld, angle %d (80/400 turn = %d), %llu edges, %llu illegal, "
      "%llu missed, %.1f ms\n",
      static_cast<long long>(source_->encoder(0).count()), out_[0].value, counts_to_angle(80, 400, 0),
      static_cast<unsigned long long>(c.edges), static_cast<unsigned long long>(c.illegal),
      static_cast<unsigned long long>(c.missed_edges), static_cast<double>(after - before) / 1e6);
  EXPECT_EQ(source_->encoder(0).count(), 80);
  EXPECT_EQ(out_[0].value, counts_to_angle(80, 400, 0));
  EXPECT_EQ(c.edges, 520u);
  EXPECT_EQ(c.illegal, 0u);
  EXPECT_EQ(c.missed_edges, 0u);
  EXPECT_EQ(source_->counters().late_events, 0u);
  EXPECT_EQ(source_->state(), hal::SourceState::kOk);
}

TEST_F(GpioSim, IndexHomesTheCount) {
  GpioSourceConfig c = config();
  c.encoders[0].line_index = kIndex;
  c.encoders[0].index_count = 100;
  create(c);
  step(37);
  EXPECT_EQ(latch(), 0u);  // not homed yet
  pull(kIndex, true);
  pull(kIndex, false);
  step(5);
  ASSERT_EQ(latch(), 1u);
  EXPECT_TRUE(source_->encoder(0).homed());
  EXPECT_EQ(source_->encoder(0).count(), 105);
}

TEST_F(GpioSim, LimitSwitchDebouncedOnKernelTimestamps) {
  GpioSourceConfig c = config();
  c.limits.resize(1);
  c.limits[0].input = 1;
  c.limits[0].line = kLimit;
  c.limits[0].active_low = false;
  c.limits[0].side = LimitSide::kMax;
  // The verdicts depend only on the kernel's edge timestamps and on the tick
  // times handed to latch(), chosen below from clock reads around the pulls,
  // never on how fast the pulls or the latches run. A window of 2 s keeps each
  // bounce (one sysfs write) far inside it in a TCG guest on a loaded host,
  // and costs no waiting.
  constexpr uint64_t kWindow = 2000 * kMs;
  c.limits[0].debounce_ns = kWindow;
  create(c);
  for (int i = 0; i < 5; ++i) {  // bounces, each far shorter than the window
    pull(kLimit, true);
    pull(kLimit, false);
  }
  const uint64_t before_press = monotonic_ns();  // the press's edge is stamped after this
  pull(kLimit, true);
  const uint64_t after_press = monotonic_ns();
  // Half a window after the press began, the press has not held long enough.
  ASSERT_EQ(source_->latch(before_press + kWindow / 2, out_, health_), 1u);
  EXPECT_EQ(out_[0].status, 0);
  // A window after it ended, it has: a tick time, not a sleep. Latched until
  // the press's edge has been read (a liveness bound: it is normally there already).
  const uint64_t held = after_press + 2 * kWindow;
  const uint64_t deadline = monotonic_ns() + 30'000 * kMs;
  for (;;) {
    ASSERT_EQ(source_->latch(held, out_, health_), 1u);
    if (out_[0].status == kSampleAtMaxLimit || monotonic_ns() >= deadline) break;
    usleep(1000);
  }
  EXPECT_EQ(out_[0].status, kSampleAtMaxLimit);
  std::printf(
      "limit via gpio-sim: %llu bounces ignored, press edge stamped %.3f ms after its pull began\n",
      static_cast<unsigned long long>(source_->limit(0).bounces()),
      (static_cast<double>(source_->limit(0).changed_ns() - kWindow) - static_cast<double>(before_press)) / 1e6);
  EXPECT_EQ(source_->limit(0).changes(), 1u);
  EXPECT_GE(source_->limit(0).bounces(), 5u);
  // Accepted a window after the last edge, not after an earlier bounce.
  EXPECT_GE(source_->limit(0).changed_ns(), before_press + kWindow);
  EXPECT_LE(source_->limit(0).changed_ns(), held);
}

TEST_F(GpioSim, SyncEdgeWakesTheWaiter) {
  GpioSourceConfig c = config();
  c.sync.line = kSync;
  create(c);
  uint64_t t0 = monotonic_ns();
  EXPECT_EQ(source_->wait_sync(30 * kMs).result, WaitResult::kTimeout);
  const double timeout_ms = static_cast<double>(monotonic_ns() - t0) / 1e6;
  EXPECT_GE(timeout_ms, 29.0);
  t0 = monotonic_ns();
  std::thread master([this] {
    usleep(20'000);
    pull(kSync, true);
  });
  const SyncEdge e = source_->wait_sync(30'000 * kMs);  // a liveness bound: the edge returns it at once
  const uint64_t woke = monotonic_ns();
  master.join();
  ASSERT_EQ(e.result, WaitResult::kReady);
  EXPECT_GE(e.timestamp_ns, t0 + 19 * kMs);
  EXPECT_LE(e.timestamp_ns, woke);
  std::printf("sync: timeout after %.1f ms; edge at +%.3f ms, woken %.3f ms after the edge\n", timeout_ms,
              static_cast<double>(e.timestamp_ns - t0) / 1e6, static_cast<double>(woke - e.timestamp_ns) / 1e6);
}

TEST_F(GpioSim, FaultLineDrivesTheChip) {
  GpioSourceConfig c = config();
  c.fault.line = kFault;
  create(c);
  EXPECT_EQ(value(kFault), 1);  // asserted from the start
  ASSERT_TRUE(source_->set_fault(false));
  EXPECT_EQ(value(kFault), 0);
  ASSERT_TRUE(source_->set_fault(true));
  EXPECT_EQ(value(kFault), 1);
}

TEST_F(GpioSim, FifoOverflowDetectedByReadBack) {
  create(config());
  for (int i = 0; i < 42; ++i) {  // 21 edges per line without a latch: more than the 16-event FIFO
    pos_ = (pos_ + 1) % 4;
    const uint8_t ab = kForward[pos_];
    if (i % 2 == 0)
      pull(kA, (ab & 2) != 0);
    else
      pull(kB, (ab & 1) != 0);
  }
  latch();
  const QuadratureCounters& c = source_->encoder(0).counters();
  std::printf("overflow: count %lld after 42 steps, %llu resyncs, overflow checks %llu, state %s\n",
              static_cast<long long>(source_->encoder(0).count()), static_cast<unsigned long long>(c.resyncs),
              static_cast<unsigned long long>(source_->counters().overflow_checks),
              hal::source_state_name(source_->state()));
  EXPECT_GE(source_->counters().overflow_checks, 1u);
  EXPECT_EQ(c.resyncs, 1u);  // 32 steps decoded (state 00), the lines show 42 (state 11)
  EXPECT_EQ(source_->encoder(0).count(), 32);
  EXPECT_EQ(source_->state(), hal::SourceState::kDegraded);
}

TEST_F(GpioSim, LatchDoesNotAllocate) {
  create(config());
  test::AllocationCounter counter;
  for (int i = 0; i < 200; ++i) step(i % 2 == 0 ? 3 : -2);
  const uint64_t allocations = counter.allocations();
  std::printf("200 rounds of pulls and latches: %llu heap allocations\n", static_cast<unsigned long long>(allocations));
  EXPECT_EQ(source_->encoder(0).count(), 100);
  EXPECT_EQ(allocations, 0u);
}

}  // namespace
}  // namespace sinew::hal::gpio
