#include "firmware/runtime/runtime.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>

#include "firmware/rig/loaded_rig.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "tests/sim_core/engine/rig_fixture.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/soak.hpp"
#include "tests/support/time_units.hpp"

namespace fw = sinew::firmware;
namespace hal = sinew::hal;

namespace {

using sinew::test::kMs;

// Delivers a fixed script of samples by timestamp; can be told to reject.
class ScriptedSource : public fw::InputSource {
 public:
  explicit ScriptedSource(std::vector<hal::JointSample> script) : script_(std::move(script)) {}
  const char* name() const override { return "scripted"; }
  size_t latch(uint64_t until_ns, std::span<hal::JointSample> out, fw::InputHealth& health) override {
    size_t n = 0;
    while (next_ < script_.size() && script_[next_].timestamp_ns <= until_ns && n < out.size()) {
      if (script_[next_].status == 0xEE) {
        health.reject(script_[next_].input, hal::RejectReason::kBadCrc);
      } else {
        out[n++] = script_[next_];
      }
      ++next_;
    }
    return n;
  }
  fw::SourceState state() const override { return fw::SourceState::kOk; }
  std::string status_line() const override { return "scripted"; }

 private:
  std::vector<hal::JointSample> script_;
  size_t next_ = 0;
};

// Keeps a hash-like fingerprint of every frame, allocation-free.
class FingerprintSink : public fw::OutputSink {
 public:
  const char* name() const override { return "fingerprint"; }
  bool write(const hal::PoseFrame& f) override {
    for (uint32_t v = 0; v < f.vertex_count; ++v)
      for (int c = 0; c < 3; ++c) fold(static_cast<uint32_t>(f.position[c][v]));
    for (uint32_t i = 0; i < f.input_count; ++i) fold(f.input_status[i]);
    for (uint32_t i = 0; i < f.input_count && i < last_status_.size(); ++i) last_status_[i] = f.input_status[i];
    return true;
  }
  void flush() override {}
  std::string status_line() const override { return ""; }
  uint64_t value = 1469598103934665603u;
  std::array<uint8_t, 64> last_status_{};  // fixed: the sink must not allocate either

 private:
  void fold(uint32_t x) { value = (value ^ x) * 1099511628211u; }
};

using sinew::test::degrees;
using sinew::test::LoadedRig;

std::vector<hal::JointSample> script() {
  std::vector<hal::JointSample> s;
  for (uint64_t t = 1; t <= 100; ++t) {
    s.push_back({3, degrees(static_cast<double>(t)), t * kMs, 0});               // elbow flexes, every ms
    if (t <= 20) s.push_back({4, degrees(static_cast<double>(t)), t * kMs, 0});  // twist stops at 20 ms
  }
  s.push_back({3, degrees(30), 50 * kMs, 0xEE});  // a corrupted frame
  std::stable_sort(s.begin(), s.end(), [](auto& a, auto& b) { return a.timestamp_ns < b.timestamp_ns; });
  return s;
}

uint64_t run(const sinew::rig::Rig& rig, FingerprintSink** sink_out, fw::Runtime* rt) {
  std::vector<fw::InputLimits> limits(rig.input_count, fw::InputLimits{degrees(-170), degrees(170), 15 * kMs});
  std::string error;
  EXPECT_TRUE(rt->init(rig, limits, 0, &error)) << error;
  rt->add_source(std::make_unique<ScriptedSource>(script()));
  auto sink = std::make_unique<FingerprintSink>();
  *sink_out = sink.get();
  rt->add_sink(std::move(sink));
  sinew::test::AllocationCounter allocations;
  for (uint64_t t = 1; t <= 100; ++t) rt->step(t * kMs);
  EXPECT_EQ(allocations.allocations(), 0u);
  return (*sink_out)->value;
}

}  // namespace

TEST(Runtime, StaleInputsHoldAndIdenticalInputsGiveIdenticalFrames) {
  const LoadedRig arm(sinew::rigc::builtin_arm());
  ASSERT_TRUE(arm.ok());
  fw::Runtime a, b;
  FingerprintSink *sa = nullptr, *sb = nullptr;
  const uint64_t fa = run(arm.rig(), &sa, &a);
  const uint64_t fb = run(arm.rig(), &sb, &b);
  EXPECT_EQ(fa, fb);
  // Twist (input 4) stopped at 20 ms with a 15 ms timeout: stale, holding 20 degrees.
  EXPECT_TRUE(sa->last_status_[4] & hal::kJointStale);
  EXPECT_EQ(a.health().values()[4], degrees(20));
  // Elbow kept streaming: fresh, last value 100 degrees; the corrupt frame was counted.
  EXPECT_FALSE(sa->last_status_[3] & hal::kJointStale);
  EXPECT_EQ(a.health().values()[3], degrees(100));
  EXPECT_EQ(a.health().counters(3).rejected[static_cast<int>(hal::RejectReason::kBadCrc)], 1u);
  // Inputs that never sent are stale from the first timeout on and hold rest.
  EXPECT_TRUE(sa->last_status_[0] & hal::kJointStale);
  EXPECT_EQ(a.ticks(), 100u);
}

TEST(Runtime, ClampedJointsAreFlaggedInTheFrame) {
  const LoadedRig arm(sinew::rigc::builtin_arm());
  ASSERT_TRUE(arm.ok());
  fw::Runtime rt;
  std::vector<fw::InputLimits> limits(arm.rig().input_count, fw::InputLimits{degrees(-170), degrees(170), 0});
  std::string error;
  ASSERT_TRUE(rt.init(arm.rig(), limits, 0, &error));
  rt.add_source(
      std::make_unique<ScriptedSource>(std::vector<hal::JointSample>{{3, degrees(160), 1, 0}}));  // elbow limit 150
  const hal::PoseFrame& f = rt.step(kMs);
  EXPECT_TRUE(f.input_status[3] & hal::kJointClampedStatus);
  EXPECT_FALSE(f.input_status[0] & hal::kJointClampedStatus);
}

// The runtime marks every input a source has delivered as measured, so the
// hand's DIP coupling (2/3 of the PIP) adds nothing to a DIP a glove
// measures. Index PIP at 60 degrees: a DIP no source sends bends 40 degrees
// (the coupling alone); a DIP sent at 30 bends 30, not 70.
TEST(Runtime, ADipASourceMeasuresIsNotCoupledToItsPip) {
  const LoadedRig hand(sinew::rigc::builtin_hand());
  ASSERT_TRUE(hand.ok());
  constexpr uint32_t kIndexPip = 8, kIndexDip = 9, kIndexDipJoint = 6;
  for (const bool dip_sent : {false, true}) {
    fw::Runtime rt;
    std::vector<fw::InputLimits> limits(hand.rig().input_count, fw::InputLimits{degrees(-170), degrees(170), 0});
    std::string error;
    ASSERT_TRUE(rt.init(hand.rig(), limits, 0, &error)) << error;
    std::vector<hal::JointSample> samples{{kIndexPip, degrees(60), 1, 0}};
    if (dip_sent) samples.push_back({kIndexDip, degrees(30), 1, 0});
    rt.add_source(std::make_unique<ScriptedSource>(samples));
    rt.step(kMs);
    const sinew::fx::Quat q = rt.engine().locals[kIndexDipJoint].rotation;
    const double sign = q.w < 0 ? -1.0 : 1.0;
    const double angle = 2 * std::atan2(sign * q.y, sign * static_cast<double>(q.w)) * 180 / 3.14159265358979323846;
    EXPECT_NEAR(angle, dip_sent ? 30.0 : 40.0, 1e-3) << (dip_sent ? "DIP sent" : "DIP not sent");
  }
}

// The built-in arm's compiled SPH elbow in the runtime, fed by the rig's
// external force input: 1000 ticks (300 under qemu) without a heap call, the
// force logged in the frame, and the joint's yield flagged on the elbow's
// input once the ramp passes the Tresca limit.
TEST(Runtime, SphLayerOnAnExternalForceInputNeverAllocates) {
  fw::LoadedRig rig;
  std::string error;
  ASSERT_TRUE(fw::load_rig("arm", "", &rig, &error)) << error;
  ASSERT_EQ(rig.input_count(), rig.rig.input_count + 1);
  ASSERT_EQ(rig.input_names.back(), "elbow.force");
  const auto force = static_cast<uint16_t>(rig.input_count() - 1);

  const uint64_t ticks = sinew::test::emulated() ? 300 : 1000, ramp = ticks / 2;
  std::vector<hal::JointSample> samples;  // 0 -> 40 N over the first half, then held
  for (uint64_t t = 1; t <= ticks; ++t)
    samples.push_back({force, static_cast<int32_t>(std::min(t, ramp) * 40 * 65536 / ramp), t * kMs, 0});
  fw::Runtime rt;
  sinew::pipeline::PipelineOptions options;
  options.stages = sinew::pipeline::StageSet::none();
  options.stages.set(sinew::pipeline::Stage::kSph, true);
  const std::vector<fw::InputLimits> limits(rig.input_count(), fw::InputLimits{INT32_MIN, INT32_MAX, 0});
  ASSERT_TRUE(rt.init(rig.rig, rig.layers, options, limits, 0, &error)) << error;
  rt.add_source(std::make_unique<ScriptedSource>(std::move(samples)));
  auto sink = std::make_unique<FingerprintSink>();
  FingerprintSink* fingerprint = sink.get();
  rt.add_sink(std::move(sink));

  sinew::test::AllocationCounter allocations;
  const hal::PoseFrame* frame = nullptr;
  uint64_t first_yield_tick = 0;
  for (uint64_t t = 1; t <= ticks; ++t) {
    frame = &rt.step(t * kMs);
    if (first_yield_tick == 0 && (frame->input_status[3] & hal::kJointYielded)) first_yield_tick = t;
  }
  std::printf("sph layer: %llu heap allocations in %llu ticks; yielded at tick %llu (%.1f N); layer errors %llu\n",
              static_cast<unsigned long long>(allocations.allocations()), static_cast<unsigned long long>(ticks),
              static_cast<unsigned long long>(first_yield_tick),
              static_cast<double>(std::min(first_yield_tick, ramp)) * 40 / static_cast<double>(ramp),
              static_cast<unsigned long long>(rt.layer_errors()));
  EXPECT_EQ(allocations.allocations(), 0u);
  EXPECT_EQ(rt.layer_errors(), 0u);
  ASSERT_EQ(frame->input_count, rig.input_count());
  EXPECT_EQ(frame->input_value[force], 40 * 65536);
  EXPECT_GT(first_yield_tick, 0u) << "40 N is past the elbow's Tresca limit";
  EXPECT_TRUE(fingerprint->last_status_[3] & hal::kJointYielded);
}

// Every layer the built-in arm carries, at once, in the runtime: no heap
// call across the ticks, no layer error.
TEST(Runtime, AllLayersAtOnceNeverAllocate) {
  fw::LoadedRig rig;
  std::string error;
  ASSERT_TRUE(fw::load_rig("arm", "", &rig, &error)) << error;
  fw::Runtime rt;
  const std::vector<fw::InputLimits> limits(rig.input_count(), fw::InputLimits{INT32_MIN, INT32_MAX, 0});
  ASSERT_TRUE(rt.init(rig.rig, rig.layers, {}, limits, 0, &error)) << error;
  const uint64_t ticks = sinew::test::emulated() ? 20 : 100;
  std::vector<hal::JointSample> samples;  // the elbow flexes 0 -> 90 degrees
  for (uint64_t t = 1; t <= ticks; ++t)
    samples.push_back(
        {3, static_cast<int32_t>(static_cast<double>(t) / static_cast<double>(ticks) * 1073741824.0), t * kMs, 0});
  rt.add_source(std::make_unique<ScriptedSource>(std::move(samples)));
  rt.step(kMs);  // first tick outside the count: sources may size buffers lazily
  sinew::test::AllocationCounter allocations;
  for (uint64_t t = 2; t <= ticks; ++t) rt.step(t * kMs);
  EXPECT_EQ(allocations.allocations(), 0u);
  EXPECT_EQ(rt.layer_errors(), 0u) << rt.last_layer_error();
  for (uint32_t s = 0; s < sinew::pipeline::kStageCount; ++s)
    EXPECT_TRUE(sinew::pipeline::pipeline_stage_on(rt.pipeline(), static_cast<sinew::pipeline::Stage>(s)));
}
