#include "shadow_pipeline.hpp"

#include <algorithm>

#include "hal/common/monotonic_clock.hpp"

namespace sinew::view {

bool ShadowPipeline::init(const ViewRig& rig, const pipeline::PipelineOptions& options, std::string* error) {
  rig_ = &rig;
  options_ = options;
  rate_known_ = options.tick_hz != 0;
  have_first_ = false;
  return reset(error);
}

bool ShadowPipeline::reset(std::string* error) {
  const rig::Rig& r = rig_->loaded.rig;
  arena_.assign(pipeline::pipeline_state_bytes(r, rig_->loaded.layers, options_) / 8 + 1, 0);
  pipeline_ = {};
  const pipeline::PipelineStatus st =
      pipeline::pipeline_init(r, rig_->loaded.layers, options_, arena_.data(), arena_.size() * 8, &pipeline_);
  if (!st.ok()) return *error = std::string("layers: ") + st.message, false;
  for (auto& axis : plain_) axis.assign(r.vertex_count(), 0);
  steps_ = 0;
  return true;
}

ShadowStep ShadowPipeline::step_frame(const hal::output::DecodedPose& pose) {
  if (!rate_known_ && !have_first_) {
    have_first_ = true;
    first_tick_ = pose.tick;
    first_ns_ = pose.timestamp_ns;
    first_inputs_ = pose.input_value;
  } else if (!rate_known_ && pose.tick > first_tick_ && pose.timestamp_ns > first_ns_) {
    rate_known_ = true;
    const double hz =
        1e9 * static_cast<double>(pose.tick - first_tick_) / static_cast<double>(pose.timestamp_ns - first_ns_);
    const auto rate = static_cast<uint32_t>(std::min(hz, 1e6) + 0.5);
    const pipeline::PipelineOptions before = options_;
    options_.tick_hz = rate;
    std::string error;
    if (!reset(&error)) {
      // A rate the layers refuse (e.g. SPH needing over 16 substeps): the
      // rig's own rate, as before.
      options_ = before;
      (void)reset(&error);
    }
    (void)step(first_tick_, first_inputs_);
  }
  return step(pose.tick, pose.input_value);
}

ShadowStep ShadowPipeline::step(uint64_t tick, std::span<const int32_t> inputs) {
  // As firmware::step_pipeline does, stage by stage, each timed; after the
  // skinning stage the output is plain skinning, kept for the displacement.
  ShadowStep out;
  out.tick = tick;
  if (inputs.size() < pipeline_.input_count) return out.layer_error = true, out;
  for (uint32_t s = 0; s < pipeline::kStageCount; ++s) {
    const auto stage = static_cast<pipeline::Stage>(s);
    if (!pipeline::pipeline_stage_on(pipeline_, stage)) continue;
    const uint64_t t0 = hal::monotonic_ns();
    const pipeline::PipelineStatus st = pipeline::pipeline_run_stage(&pipeline_, stage, inputs);
    out.stage_ns[s] = std::max<uint64_t>(1, hal::monotonic_ns() - t0);
    if (!st.ok()) out.layer_error = true;
    if (stage == pipeline::Stage::kSkinning)
      for (int c = 0; c < 3; ++c) {
        const auto& v = pipeline_.engine.vertices.position[c];
        std::copy(v.begin(), v.end(), plain_[c].begin());
      }
  }
  ++steps_;
  return out;
}

}  // namespace sinew::view
