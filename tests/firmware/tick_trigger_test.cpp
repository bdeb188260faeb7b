// Input-triggered ticks on simulated time: a tick starts once every input of
// its slot has arrived, before the slot's deadline; a silent input leaves the
// tick to the deadline, where it runs on held inputs flagged as a periodic
// tick flags them; the same latched inputs give the same frames in both modes.
#include "firmware/runtime/tick_trigger.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>

#include "firmware/runtime/runtime.hpp"
#include "hal/can/can_input_source.hpp"
#include "hal/can/joint_stream_decoder.hpp"
#if SINEW_SIMULATED_DEVICES
#include "hal/can/sim/simulated_rig_bus.hpp"
#endif
#include "host_tools/rigc/builtin_rigs.hpp"
#include "tests/sim_core/engine/rig_fixture.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/time_units.hpp"

namespace fw = sinew::firmware;
namespace hal = sinew::hal;

namespace {

using sinew::test::kMs;
using sinew::test::kUs;

constexpr uint64_t kTickPeriod = 1 * kMs;
constexpr uint64_t kPoll = 10 * kUs;

// Time that only moves when the loop sleeps: no wall clock in these tests.
class SimulatedWaitClock final : public fw::WaitClock {
 public:
  uint64_t now_ns() override { return now; }
  void sleep_until_ns(uint64_t t) override {
    if (t > now) now = t;
    ++sleeps;
  }
  uint64_t now = 0;
  uint64_t sleeps = 0;
};

// A script of samples for a fixed set of inputs; complete when each of them
// has an unlatched sample stamped <= now.
class ArrivingSource final : public fw::InputSource {
 public:
  ArrivingSource(std::vector<hal::JointSample> script, std::vector<uint16_t> inputs)
      : script_(std::move(script)), inputs_(std::move(inputs)) {}
  const char* name() const override { return "arriving"; }
  size_t latch(uint64_t until_ns, std::span<hal::JointSample> out, fw::InputHealth&) override {
    size_t n = 0;
    while (next_ < script_.size() && script_[next_].timestamp_ns <= until_ns && n < out.size())
      out[n++] = script_[next_++];
    return n;
  }
  fw::SourceState state() const override { return fw::SourceState::kOk; }
  std::string status_line() const override { return "arriving"; }
  uint8_t arrival_signals() const override { return hal::kSignalsComplete; }
  hal::Arrival arrival(uint64_t now_ns) override {
    ++arrival_calls;
    std::array<bool, 64> seen{};
    for (size_t k = next_; k < script_.size() && script_[k].timestamp_ns <= now_ns; ++k)
      seen[script_[k].input % seen.size()] = true;
    bool complete = true;
    for (uint16_t i : inputs_) complete = complete && seen[i % seen.size()];
    return {complete, false};
  }
  uint64_t arrival_calls = 0;

 private:
  std::vector<hal::JointSample> script_;
  std::vector<uint16_t> inputs_;
  size_t next_ = 0;
};

// One hash per frame, in slot order, into storage sized before the ticks.
class FrameHashSink final : public fw::OutputSink {
 public:
  explicit FrameHashSink(size_t frames) { hashes.reserve(frames); }
  const char* name() const override { return "frame-hash"; }
  bool write(const hal::PoseFrame& f) override {
    uint64_t h = 1469598103934665603u;
    const auto fold = [&](uint32_t x) { h = (h ^ x) * 1099511628211u; };
    fold(static_cast<uint32_t>(f.tick));
    for (uint32_t v = 0; v < f.vertex_count; ++v)
      for (int c = 0; c < 3; ++c) fold(static_cast<uint32_t>(f.position[c][v]));
    for (uint32_t i = 0; i < f.input_count; ++i) {
      fold(static_cast<uint32_t>(f.input_value[i]));
      fold(f.input_status[i]);
    }
    if (hashes.size() < hashes.capacity()) hashes.push_back(h);
    return true;
  }
  void flush() override {}
  std::string status_line() const override { return ""; }
  std::vector<uint64_t> hashes;
};

using sinew::test::degrees;
using sinew::test::LoadedRig;

// Elbow (3) and twist (4) at 500 Hz: the elbow at 0.3 ms past every second
// tick, the twist `lag` later; the twist goes silent from `twist_stops_ns`.
std::vector<hal::JointSample> two_inputs(uint64_t until_ns, uint64_t lag, uint64_t twist_stops_ns) {
  std::vector<hal::JointSample> s;
  for (uint64_t t = 300 * kUs, k = 0; t <= until_ns; t += 2 * kMs, ++k) {
    s.push_back({3, degrees(static_cast<double>(k % 90)), t, 0});
    if (t + lag < twist_stops_ns) s.push_back({4, degrees(-static_cast<double>(k % 45)), t + lag, 0});
  }
  return s;
}

struct ModeRun {
  std::vector<fw::TriggeredTick> ticks;
  std::vector<uint64_t> frames;
  std::vector<uint8_t> twist_status;
  std::vector<int32_t> twist_value;
};

// `slots` ticks of the runtime on `trigger`, on simulated time. Only the
// twist can go stale (3 ms timeout); the others never time out.
ModeRun run_mode(const sinew::rig::Rig& rig, fw::TickTrigger trigger, std::vector<hal::JointSample> script,
                 size_t slots) {
  std::vector<fw::InputLimits> limits(rig.input_count, fw::InputLimits{degrees(-170), degrees(170), 0});
  limits[4].timeout_ns = 3 * kMs;
  fw::Runtime rt;
  std::string error;
  EXPECT_TRUE(rt.init(rig, limits, 0, &error)) << error;
  rt.add_source(std::make_unique<ArrivingSource>(std::move(script), std::vector<uint16_t>{3, 4}));
  auto sink = std::make_unique<FrameHashSink>(slots);
  FrameHashSink* hashes = sink.get();
  rt.add_sink(std::move(sink));
  ModeRun run;
  run.ticks.reserve(slots);
  run.twist_status.reserve(slots);
  run.twist_value.reserve(slots);
  SimulatedWaitClock clock;
  fw::TriggeredTickClock ticks(trigger, kTickPeriod, kTickPeriod, kPoll);
  sinew::test::AllocationCounter allocations;
  for (size_t slot = 0; slot < slots; ++slot) {
    const fw::TriggeredTick tick = ticks.wait_next(rt.sources(), clock);
    const hal::PoseFrame& f = rt.step(tick.time_ns, tick.deadline_ns / kTickPeriod - 1);
    run.ticks.push_back(tick);
    run.twist_status.push_back(f.input_status[4]);
    run.twist_value.push_back(f.input_value[4]);
  }
  EXPECT_EQ(allocations.allocations(), 0u) << "a triggered tick must not allocate";
  run.frames = hashes->hashes;
  return run;
}

}  // namespace

TEST(TickTrigger, StepsWhenEveryInputHasArrivedBeforeTheDeadline) {
  const LoadedRig arm(sinew::rigc::builtin_arm());
  ASSERT_TRUE(arm.ok());
  const uint64_t lag = 50 * kUs;
  const ModeRun run = run_mode(arm.rig(), fw::TickTrigger::kInputs, two_inputs(20 * kMs, lag, UINT64_MAX), 20);
  ASSERT_EQ(run.ticks.size(), 20u);
  for (size_t slot = 0; slot < run.ticks.size(); ++slot) {
    const fw::TriggeredTick& t = run.ticks[slot];
    EXPECT_EQ(t.deadline_ns, (slot + 1) * kTickPeriod) << "one tick per slot, in slot order";
    if (slot % 2 == 0) {
      // The set completes with the twist, 0.35 ms past the previous deadline:
      // the tick starts at the first poll after it, not at 1 ms.
      const uint64_t complete = slot * kTickPeriod + 300 * kUs + lag;
      EXPECT_TRUE(t.triggered) << "slot " << slot;
      EXPECT_GE(t.time_ns, complete) << "slot " << slot;
      EXPECT_LE(t.time_ns, complete + kPoll) << "slot " << slot;
      EXPECT_LT(t.time_ns, t.deadline_ns);
    } else {
      // Nothing new arrives in odd slots: the deadline runs the tick.
      EXPECT_FALSE(t.triggered) << "slot " << slot;
      EXPECT_EQ(t.time_ns, t.deadline_ns);
    }
  }
  // The twist sample latched by an early tick is the one sent in its slot.
  EXPECT_EQ(run.twist_value[4], degrees(-2.0));
  EXPECT_EQ(run.twist_status[4] & hal::kJointStale, 0);
}

TEST(TickTrigger, APartialSetWaitsForItsLastInput) {
  const LoadedRig arm(sinew::rigc::builtin_arm());
  ASSERT_TRUE(arm.ok());
  // The twist lags the elbow by 0.6 ms: the tick waits for it, not for the elbow.
  const ModeRun run = run_mode(arm.rig(), fw::TickTrigger::kInputs, two_inputs(10 * kMs, 600 * kUs, UINT64_MAX), 10);
  ASSERT_TRUE(run.ticks[0].triggered);
  EXPECT_GE(run.ticks[0].time_ns, 900 * kUs);
  EXPECT_LE(run.ticks[0].time_ns, 900 * kUs + kPoll);
}

TEST(TickTrigger, ASilentInputFallsBackToTheDeadlineFlaggedAsAPeriodicTick) {
  const LoadedRig arm(sinew::rigc::builtin_arm());
  ASSERT_TRUE(arm.ok());
  constexpr size_t kSlots = 30;
  const uint64_t twist_stops = 10 * kMs;
  const auto script = two_inputs(kSlots * kMs, 50 * kUs, twist_stops);
  const ModeRun periodic = run_mode(arm.rig(), fw::TickTrigger::kPeriodic, script, kSlots);
  const ModeRun inputs = run_mode(arm.rig(), fw::TickTrigger::kInputs, script, kSlots);
  size_t stale_from = 0;
  for (size_t slot = 0; slot < kSlots; ++slot) {
    const uint64_t deadline = (slot + 1) * kTickPeriod;
    EXPECT_FALSE(periodic.ticks[slot].triggered);
    EXPECT_EQ(periodic.ticks[slot].time_ns, deadline);
    if (deadline > twist_stops) {
      // The twist never completes the set again: every tick is the fallback,
      // on the deadline's time, with the twist held and flagged as periodic does.
      EXPECT_FALSE(inputs.ticks[slot].triggered) << "slot " << slot;
      EXPECT_EQ(inputs.ticks[slot].time_ns, deadline) << "slot " << slot;
    }
    EXPECT_EQ(inputs.twist_status[slot], periodic.twist_status[slot]) << "slot " << slot;
    EXPECT_EQ(inputs.twist_value[slot], periodic.twist_value[slot]) << "slot " << slot;
    if (stale_from == 0 && (inputs.twist_status[slot] & hal::kJointStale)) stale_from = slot;
  }
  // Last twist sample at 8.35 ms, 3 ms timeout: stale from the 12 ms deadline (slot 11).
  EXPECT_EQ(stale_from, 11u);
  EXPECT_EQ(inputs.twist_value.back(), degrees(-4.0));
  EXPECT_EQ(inputs.frames, periodic.frames);
}

TEST(TickTrigger, TheSameLatchedInputsGiveTheSameFramesInBothModes) {
  const LoadedRig arm(sinew::rigc::builtin_arm());
  ASSERT_TRUE(arm.ok());
  constexpr size_t kSlots = 200;
  // Jittered arrivals (a fixed LCG), still one set per two slots.
  std::vector<hal::JointSample> script;
  uint32_t lcg = 12345;
  for (uint64_t k = 0; 2 * k * kMs < kSlots * kMs; ++k) {
    lcg = lcg * 1664525u + 1013904223u;
    const uint64_t t = 2 * k * kMs + 100 * kUs + (lcg >> 16) % 500 * kUs;
    script.push_back({3, static_cast<int32_t>(lcg) / 32, t, 0});
    script.push_back({4, static_cast<int32_t>(lcg * 7u) / 32, t + (lcg >> 8) % 300 * kUs, 0});
  }
  std::stable_sort(script.begin(), script.end(), [](auto& a, auto& b) { return a.timestamp_ns < b.timestamp_ns; });
  const ModeRun periodic = run_mode(arm.rig(), fw::TickTrigger::kPeriodic, script, kSlots);
  const ModeRun inputs = run_mode(arm.rig(), fw::TickTrigger::kInputs, script, kSlots);
  size_t triggered = 0;
  for (const fw::TriggeredTick& t : inputs.ticks) triggered += t.triggered ? 1 : 0;
  EXPECT_EQ(triggered, kSlots / 2) << "every set triggers its slot's tick";
  ASSERT_EQ(inputs.frames.size(), kSlots);
  EXPECT_EQ(inputs.frames, periodic.frames);
}

TEST(TickTrigger, NoSourceThatSignalsMeansEveryTickIsTheFallback) {
  std::vector<std::unique_ptr<fw::InputSource>> none;
  SimulatedWaitClock clock;
  fw::TriggeredTickClock ticks(fw::TickTrigger::kInputs, kTickPeriod, kTickPeriod, kPoll);
  const fw::TriggeredTick t = ticks.wait_next(none, clock);
  EXPECT_FALSE(t.triggered);
  EXPECT_EQ(t.time_ns, kTickPeriod);
  EXPECT_EQ(clock.now, kTickPeriod);
  EXPECT_EQ(fw::trigger_signal(fw::TickTrigger::kPeriodic), hal::kSignalsNothing);
}

TEST(TickTrigger, ALateLoopSkipsAheadInsteadOfBursting) {
  std::vector<std::unique_ptr<fw::InputSource>> none;
  SimulatedWaitClock clock;
  fw::TriggeredTickClock ticks(fw::TickTrigger::kInputs, kTickPeriod, kTickPeriod, kPoll);
  clock.now = 5 * kTickPeriod + 10 * kUs;  // the loop stalled for five periods
  const fw::TriggeredTick t = ticks.wait_next(none, clock);
  EXPECT_EQ(ticks.skipped_ticks(), 4u);
  EXPECT_EQ(t.deadline_ns, 5 * kTickPeriod);
  EXPECT_FALSE(ticks.finished_late(5 * kTickPeriod + 20 * kUs));
}

#if SINEW_SIMULATED_DEVICES
// The simulated rig on the CAN bus with a sync frame after each set: the
// sync trigger starts the tick on it, and the tick latches every joint.
TEST(TickTrigger, ACanSyncFrameStartsTheTick) {
  const LoadedRig arm(sinew::rigc::builtin_arm());
  ASSERT_TRUE(arm.ok());
  std::vector<hal::sim::InputRange> ranges(arm.rig().input_count);
  for (const sinew::rig::JointRecord& j : arm.rig().joints)
    for (uint32_t d = 0; d < j.dof_count; ++d) ranges[j.first_input + d] = {j.dof_min[d], j.dof_max[d]};
  for (const fw::TickTrigger trigger : {fw::TickTrigger::kSync, fw::TickTrigger::kInputs}) {
    hal::sim::SimulatedRigOptions options;
    options.period_ns = 2 * kMs;
    options.offset_ns = 300 * kUs;
    options.send_sync = true;
    std::string error;
    ASSERT_TRUE(hal::sim::SimulatedRigBus::validate(options, ranges.size(), &error)) << error;
    auto bus = std::make_unique<hal::sim::SimulatedRigBus>(hal::sim::RigMotion(ranges), options, 0);
    auto decoder = std::make_unique<hal::can::JointStreamDecoder>();
    ASSERT_TRUE(decoder->configure(bus->stream_config(), &error)) << error;
    const hal::can::SyncFrameOptions sync{true, {options.sync_id, false}};
    auto source = hal::can::CanInputSource::create("can", std::move(bus), std::move(decoder), 128, 0, &error, sync);
    ASSERT_NE(source, nullptr) << error;
    EXPECT_EQ(source->arrival_signals(), hal::kSignalsComplete | hal::kSignalsSync);
    hal::can::CanInputSource* can = source.get();
    std::vector<fw::InputLimits> limits(arm.rig().input_count);
    fw::Runtime rt;
    ASSERT_TRUE(rt.init(arm.rig(), limits, 0, &error)) << error;
    rt.add_source(std::move(source));
    SimulatedWaitClock clock;
    fw::TriggeredTickClock ticks(trigger, kTickPeriod, kTickPeriod, kPoll);
    for (uint64_t slot = 0; slot < 6; ++slot) {
      const fw::TriggeredTick t = ticks.wait_next(rt.sources(), clock);
      rt.step(t.time_ns, slot);
      if (slot % 2 == 0) {
        const uint64_t sent = slot * kTickPeriod + 300 * kUs;
        EXPECT_TRUE(t.triggered) << fw::tick_trigger_name(trigger) << " slot " << slot;
        EXPECT_GE(t.time_ns, sent);
        EXPECT_LE(t.time_ns, sent + kPoll);
        // Every joint's frame of the set was latched by this tick.
        for (uint32_t i = 0; i < arm.rig().input_count; ++i) EXPECT_EQ(rt.health().counters(i).accepted, slot / 2 + 1);
      } else {
        EXPECT_FALSE(t.triggered) << fw::tick_trigger_name(trigger) << " slot " << slot;
      }
    }
    // The sync frames were watched, never decoded: no unknown-id rejection.
    EXPECT_EQ(rt.health().unassigned().rejected[static_cast<int>(hal::RejectReason::kUnknownId)], 0u);
    EXPECT_NE(can->status_line().find("sync frames 3"), std::string::npos) << can->status_line();
    EXPECT_EQ(ticks.triggered_ticks(), 3u);
    EXPECT_EQ(ticks.fallback_ticks(), 3u);
  }
}
#endif  // SINEW_SIMULATED_DEVICES
