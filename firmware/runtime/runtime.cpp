#include "runtime.hpp"

#include <algorithm>
#include <cstring>

#include "hal/common/monotonic_clock.hpp"

namespace sinew::firmware {

namespace {

uint64_t monotonic_now(void*) { return hal::monotonic_ns(); }

}  // namespace

bool Runtime::init(const rig::Rig& rig, const pipeline::LayerSet& layers, const pipeline::PipelineOptions& options,
                   std::span<const InputLimits> limits, uint64_t start_ns, std::string* error) {
  // The rig's inputs first, then its external inputs (layer signals such as
  // a measured force): fed, checked and logged alike; the skeleton reads only
  // the rig's.
  if (limits.size() < rig.input_count + layers.external_count())
    return *error = "one input limit per rig input and per external input is required", false;
  rig_ = &rig;
  pipeline_arena_.assign(pipeline::pipeline_state_bytes(rig, layers, options) / 8 + 1, 0);
  const pipeline::PipelineStatus ps =
      pipeline::pipeline_init(rig, layers, options, pipeline_arena_.data(), pipeline_arena_.size() * 8, &pipeline_);
  if (!ps.ok()) return *error = std::string("layers: ") + ps.message, false;
  const engine::Engine& engine = pipeline_.engine;
  const std::vector<int32_t> rest(limits.size(), 0);
  health_.init(limits, rest, start_ns);
  samples_.assign(kMaxSamplesPerTick, hal::JointSample{});
  input_status_.assign(limits.size(), 0);
  pipeline_flags_.assign(limits.size(), 0);
  measured_.assign(rig.input_count, 0);
  pipeline::pipeline_set_measured_inputs(&pipeline_, measured_);
  frame_ = {};
  frame_.length_exponent = rig.length_exponent;
  frame_.vertex_count = rig.vertex_count();
  for (int c = 0; c < 3; ++c) {
    frame_.position[c] = engine.vertices.position[c].data();
    frame_.normal[c] = engine.vertices.normal[c].empty() ? nullptr : engine.vertices.normal[c].data();
  }
  frame_.input_count = static_cast<uint32_t>(limits.size());
  frame_.input_value = health_.values().data();
  frame_.input_status = input_status_.data();
  stage_ns_.assign(pipeline::kStageCount, 0);
  frame_.stage_count = pipeline::kStageCount;
  frame_.stage_ns = stage_ns_.data();
  return true;
}

const hal::PoseFrame& Runtime::step(uint64_t tick_ns, uint64_t tick_index) {
  health_.begin_tick();
  for (const auto& source : sources_) {
    const size_t n = source->latch(tick_ns, samples_, health_);
    health_.apply(std::span<const hal::JointSample>(samples_.data(), n));
  }
  health_.end_tick(tick_ns);
  // A DOF some source has measured keeps the measurement: synergies no longer
  // add to it (the coupling models what is not measured). Once measured, it
  // stays so; a stale one holds its last measured value.
  for (uint32_t i = 0; i < measured_.size(); ++i)
    if (measured_[i] == 0 && health_.counters(i).accepted > 0) measured_[i] = 1;
  // The pipeline times its stages on the monotonic clock: the statistics
  // show every layer's share of the tick.
  const pipeline::StepProbe probe{monotonic_now, nullptr, nullptr};
  pipeline::StepReport report;
  report.input_flags = pipeline_flags_;
  const pipeline::PipelineStatus st = pipeline::pipeline_step(&pipeline_, health_.values(), &probe, &report);
  for (uint32_t s = 0; s < pipeline::kStageCount; ++s) {
    const bool ran = report.ran.has(static_cast<pipeline::Stage>(s));
    stage_ns_[s] = ran ? static_cast<uint32_t>(std::min<uint64_t>(report.stage_ns[s], UINT32_MAX)) : 0;
    if (!ran) continue;
    stage_times_.total_ns[s] += report.stage_ns[s];
    stage_times_.max_ns[s] = std::max(stage_times_.max_ns[s], report.stage_ns[s]);
  }
  ++stage_times_.ticks;
  if (!st.ok()) {
    ++layer_errors_;
    static_assert(sizeof(last_layer_error_) == sizeof(st.message));
    std::memcpy(last_layer_error_, st.message, sizeof(last_layer_error_));
  }
  // Per-input status: the health bits plus what the pipeline reported.
  const std::span<const uint8_t> hs = health_.status();
  for (size_t i = 0; i < input_status_.size(); ++i) {
    uint8_t status = hs[i];
    if ((pipeline_flags_[i] & pipeline::kInputClamped) != 0) status |= hal::kJointClampedStatus;
    if ((pipeline_flags_[i] & pipeline::kInputYielded) != 0) status |= hal::kJointYielded;
    if (i < measured_.size() && measured_[i] != 0) status |= hal::kJointMeasured;
    input_status_[i] = status;
  }
  frame_.tick = tick_index;
  ++tick_;
  frame_.timestamp_ns = tick_ns;
  for (const auto& sink : sinks_)
    if (!sink->write(frame_)) ++dropped_frames_;
  return frame_;
}

void Runtime::flush() {
  for (const auto& sink : sinks_) sink->flush();
}

uint64_t Runtime::close_sinks() {
  uint64_t lost = dropped_frames_;
  for (const auto& sink : sinks_) {
    sink->close();
    lost += sink->frames_lost_after_write();
  }
  return lost;
}

}  // namespace sinew::firmware
