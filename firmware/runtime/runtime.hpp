// One tick of the daemon: latch every source up to the tick time, update
// input health (hold / stale / reject), step the engine, hand the pose frame
// to every sink. Sized once at init; a tick never allocates.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "io.hpp"
#include "sim_core/engine/engine.hpp"
#include "step_timing.hpp"

namespace sinew::firmware {

// A physical layer applied after the engine's skinning each tick (metaballs,
// bar-nets, ...): it reads the engine's joint transforms (and the held inputs) and rewrites its
// vertex positions in place. Must not allocate; returns false on an error,
// which the runtime counts (the skinned pose is kept for that tick).
class PoseLayer {
 public:
  virtual ~PoseLayer() = default;
  virtual const char* name() const = 0;
  virtual bool apply(engine::Engine& engine, std::span<const int32_t> inputs) = 0;
  // ORs the layer's per-input flags (e.g. hal::kJointYieldedStatus) into the
  // tick's input status, after the health and clamp bits.
  virtual void flag_inputs(std::span<uint8_t> /*status*/) const {}
};

class Runtime {
 public:
  // rig must outlive the runtime. limits: one per rig input.
  bool init(const rig::Rig& rig, std::span<const InputLimits> limits, uint64_t start_ns, std::string* error);
  void add_source(std::unique_ptr<InputSource> s) { sources_.push_back(std::move(s)); }
  void add_layer(std::unique_ptr<PoseLayer> l) { layers_.push_back(std::move(l)); }
  uint64_t layer_errors() const { return layer_errors_; }
  void add_sink(std::unique_ptr<OutputSink> s) { sinks_.push_back(std::move(s)); }

  // Runs the tick whose nominal time is tick_ns. Returns the frame written.
  // tick_index: the tick's slot on the schedule (start + (index + 1) x period),
  // written into the frame so that a skipped live tick shows as a gap and the
  // same slot carries the same number live, in replay and offline; by default
  // the count of steps taken.
  const hal::PoseFrame& step(uint64_t tick_ns, uint64_t tick_index);
  const hal::PoseFrame& step(uint64_t tick_ns) { return step(tick_ns, tick_); }
  void flush();

  const InputHealth& health() const { return health_; }
  const engine::Engine& engine() const { return engine_; }
  StepTiming& timing() { return timing_; }
  uint64_t ticks() const { return tick_; }
  uint64_t dropped_frames() const { return dropped_frames_; }
  std::span<const std::unique_ptr<InputSource>> sources() const { return sources_; }
  std::span<const std::unique_ptr<OutputSink>> sinks() const { return sinks_; }

 private:
  const rig::Rig* rig_ = nullptr;
  std::vector<uint64_t> engine_arena_;
  engine::Engine engine_;
  InputHealth health_;
  std::vector<hal::JointSample> samples_;
  std::vector<uint8_t> input_status_;
  std::vector<std::unique_ptr<InputSource>> sources_;
  std::vector<std::unique_ptr<OutputSink>> sinks_;
  hal::PoseFrame frame_;
  StepTiming timing_;
  uint64_t tick_ = 0;
  uint64_t dropped_frames_ = 0;
  std::vector<std::unique_ptr<PoseLayer>> layers_;
  uint64_t layer_errors_ = 0;
};

// Samples latched per source per tick at most; more wait for the next tick.
inline constexpr size_t kMaxSamplesPerTick = 4096;

}  // namespace sinew::firmware
