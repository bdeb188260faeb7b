// One tick of the daemon: latch every source up to the tick time, update
// input health (hold / stale / reject), step the pipeline, hand the pose frame
// to every sink. Sized once at init; a tick never allocates.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "io.hpp"
#include "sim_core/pipeline/pipeline.hpp"
#include "step_timing.hpp"

namespace sinew::firmware {

// Time spent in each pipeline stage (sim_core/pipeline), summed over the
// ticks since start: the statistics show each layer's share of the tick.
struct StageTimes {
  uint64_t total_ns[pipeline::kStageCount] = {};
  uint64_t max_ns[pipeline::kStageCount] = {};
  uint64_t ticks = 0;
};

class Runtime {
 public:
  // rig and layers must outlive the runtime. limits: one per rig input,
  // then one per external input. options: which compiled layers run.
  bool init(const rig::Rig& rig, const pipeline::LayerSet& layers, const pipeline::PipelineOptions& options,
            std::span<const InputLimits> limits, uint64_t start_ns, std::string* error);
  // A rig without layers (tests): plain skinning.
  bool init(const rig::Rig& rig, std::span<const InputLimits> limits, uint64_t start_ns, std::string* error) {
    return init(rig, no_layers_, {}, limits, start_ns, error);
  }
  void add_source(std::unique_ptr<InputSource> s) { sources_.push_back(std::move(s)); }
  uint64_t layer_errors() const { return layer_errors_; }
  const char* last_layer_error() const { return last_layer_error_; }
  const StageTimes& stage_times() const { return stage_times_; }
  const pipeline::Pipeline& pipeline() const { return pipeline_; }
  void add_sink(std::unique_ptr<OutputSink> s) { sinks_.push_back(std::move(s)); }

  // Runs the tick whose nominal time is tick_ns. Returns the frame written.
  // tick_index: the tick's slot on the schedule (start + (index + 1) x period),
  // written into the frame so that a skipped live tick shows as a gap and the
  // same slot carries the same number live, in replay and offline; by default
  // the count of steps taken.
  const hal::PoseFrame& step(uint64_t tick_ns, uint64_t tick_index);
  const hal::PoseFrame& step(uint64_t tick_ns) { return step(tick_ns, tick_); }
  void flush();
  // Shutdown: closes every sink (queued frames are written first). Returns
  // the frames the sinks lost in all, before or after write() accepted them.
  uint64_t close_sinks();

  const InputHealth& health() const { return health_; }
  const engine::Engine& engine() const { return pipeline_.engine; }
  StepTiming& timing() { return timing_; }
  uint64_t ticks() const { return tick_; }
  uint64_t dropped_frames() const { return dropped_frames_; }
  std::span<const std::unique_ptr<InputSource>> sources() const { return sources_; }
  std::span<const std::unique_ptr<OutputSink>> sinks() const { return sinks_; }

 private:
  const rig::Rig* rig_ = nullptr;
  std::vector<uint64_t> pipeline_arena_;
  pipeline::Pipeline pipeline_;
  pipeline::LayerSet no_layers_;
  StageTimes stage_times_;
  char last_layer_error_[192] = {};
  std::vector<uint8_t> pipeline_flags_;  // pipeline::InputFlag bits per input, last tick
  // Per rig input, 1 once a source has delivered an accepted sample for it:
  // a measured DOF, which the rig's synergies leave alone
  // (pipeline_set_measured_inputs).
  std::vector<uint8_t> measured_;
  InputHealth health_;
  std::vector<hal::JointSample> samples_;
  std::vector<uint8_t> input_status_;
  std::vector<uint32_t> stage_ns_;  // this tick's stage times, for the frame (PoseFrame::stage_ns)
  std::vector<std::unique_ptr<InputSource>> sources_;
  std::vector<std::unique_ptr<OutputSink>> sinks_;
  hal::PoseFrame frame_;
  StepTiming timing_;
  uint64_t tick_ = 0;
  uint64_t dropped_frames_ = 0;
  uint64_t layer_errors_ = 0;
};

// Samples latched per source per tick at most; more wait for the next tick.
inline constexpr size_t kMaxSamplesPerTick = 4096;

}  // namespace sinew::firmware
