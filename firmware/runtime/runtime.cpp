#include "runtime.hpp"

#include <cstring>

#include "hal/common/monotonic_clock.hpp"

namespace sinew::firmware {

pipeline::PipelineStatus step_pipeline(pipeline::Pipeline* p, std::span<const int32_t> inputs, StageTimes* times) {
  // Stage by stage, each timed: the statistics show every layer's share of
  // the tick. A failing layer keeps the pose it was given.
  pipeline::PipelineStatus failure;
  for (uint32_t s = 0; s < pipeline::kStageCount; ++s) {
    const auto stage = static_cast<pipeline::Stage>(s);
    if (!pipeline::pipeline_stage_on(*p, stage)) continue;
    const uint64_t t0 = times ? hal::monotonic_ns() : 0;
    const pipeline::PipelineStatus st = pipeline::pipeline_run_stage(p, stage, inputs);
    if (times) {
      const uint64_t dt = hal::monotonic_ns() - t0;
      times->total_ns[s] += dt;
      if (dt > times->max_ns[s]) times->max_ns[s] = dt;
    }
    if (!st.ok()) failure = st;
  }
  if (times) ++times->ticks;
  return failure;
}

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
  return true;
}

const hal::PoseFrame& Runtime::step(uint64_t tick_ns, uint64_t tick_index) {
  health_.begin_tick();
  for (const auto& source : sources_) {
    const size_t n = source->latch(tick_ns, samples_, health_);
    health_.apply(std::span<const hal::JointSample>(samples_.data(), n));
  }
  health_.end_tick(tick_ns);
  const pipeline::PipelineStatus st = step_pipeline(&pipeline_, health_.values(), &stage_times_);
  if (!st.ok()) {
    ++layer_errors_;
    static_assert(sizeof(last_layer_error_) == sizeof(st.message));
    std::memcpy(last_layer_error_, st.message, sizeof(last_layer_error_));
  }
  const engine::Engine& engine = pipeline_.engine;
  // Per-input status: health bits plus "clamped" from the joint that owns the input.
  const std::span<const uint8_t> hs = health_.status();
  for (size_t i = 0; i < input_status_.size(); ++i) input_status_[i] = hs[i];
  for (uint32_t j = 0; j < rig_->joint_count(); ++j) {
    if ((engine.joint_flags[j] & skeleton::kJointClamped) == 0) continue;
    const rig::JointRecord& r = rig_->joints[j];
    for (uint32_t d = 0; d < r.dof_count; ++d) input_status_[r.first_input + d] |= hal::kJointClampedStatus;
  }
  for (uint32_t i = 0; i < rig_->input_count; ++i)
    if (pipeline::pipeline_input_yielded(pipeline_, i)) input_status_[i] |= hal::kJointYielded;
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
