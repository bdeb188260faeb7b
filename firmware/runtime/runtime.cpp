#include "runtime.hpp"

namespace sinew::firmware {

bool Runtime::init(const rig::Rig& rig, std::span<const InputLimits> limits, uint64_t start_ns, std::string* error) {
  // The rig's inputs first, then any external inputs (layer signals such as
  // a measured force): fed, checked and logged alike; the engine reads only
  // the rig's.
  if (limits.size() < rig.input_count) return *error = "one input limit per rig input is required", false;
  rig_ = &rig;
  engine_arena_.assign(engine::engine_arena_bytes(rig) / 8 + 1, 0);
  if (!engine::engine_init(rig, engine_arena_.data(), engine_arena_.size() * 8, &engine_))
    return *error = "engine arena", false;
  const std::vector<int32_t> rest(limits.size(), 0);
  health_.init(limits, rest, start_ns);
  samples_.assign(kMaxSamplesPerTick, hal::JointSample{});
  input_status_.assign(limits.size(), 0);
  frame_ = {};
  frame_.length_exponent = rig.length_exponent;
  frame_.vertex_count = rig.vertex_count();
  for (int c = 0; c < 3; ++c) {
    frame_.position[c] = engine_.vertices.position[c].data();
    frame_.normal[c] = engine_.vertices.normal[c].empty() ? nullptr : engine_.vertices.normal[c].data();
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
  engine::engine_step(&engine_, health_.values());
  for (const auto& layer : layers_)
    if (!layer->apply(engine_, health_.values())) ++layer_errors_;
  // Per-input status: health bits plus "clamped" from the joint that owns the input.
  const std::span<const uint8_t> hs = health_.status();
  for (size_t i = 0; i < input_status_.size(); ++i) input_status_[i] = hs[i];
  for (uint32_t j = 0; j < rig_->joint_count(); ++j) {
    if ((engine_.joint_flags[j] & skeleton::kJointClamped) == 0) continue;
    const rig::JointRecord& r = rig_->joints[j];
    for (uint32_t d = 0; d < r.dof_count; ++d) input_status_[r.first_input + d] |= hal::kJointClampedStatus;
  }
  for (const auto& layer : layers_) layer->flag_inputs(input_status_);
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

}  // namespace sinew::firmware
