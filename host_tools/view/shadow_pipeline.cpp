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

namespace {

uint64_t monotonic_now(void*) { return hal::monotonic_ns(); }

// After the skinning stage the surface is plain skinning: kept for the
// displacement colouring.
void keep_plain_skin(void* context, pipeline::Stage stage, const pipeline::Pipeline& p) {
  if (stage != pipeline::Stage::kSkinning) return;
  auto* plain = static_cast<std::vector<int32_t>*>(context);
  for (int c = 0; c < 3; ++c) {
    const auto& v = p.engine.vertices.position[c];
    std::copy(v.begin(), v.end(), plain[c].begin());
  }
}

}  // namespace

ShadowStep ShadowPipeline::step(uint64_t tick, std::span<const int32_t> inputs) {
  // The daemon's step (pipeline_step), timed on this host's clock.
  ShadowStep out;
  out.tick = tick;
  const pipeline::StepProbe probe{monotonic_now, keep_plain_skin, plain_};
  pipeline::StepReport report;
  out.layer_error = !pipeline::pipeline_step(&pipeline_, inputs, &probe, &report).ok();
  for (uint32_t s = 0; s < pipeline::kStageCount; ++s)
    if (report.ran.has(static_cast<pipeline::Stage>(s))) out.stage_ns[s] = std::max<uint64_t>(1, report.stage_ns[s]);
  ++steps_;
  return out;
}

}  // namespace sinew::view
