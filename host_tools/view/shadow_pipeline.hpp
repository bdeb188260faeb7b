// The viewer's own copy of the daemon's pipeline, stepped with the inputs
// every frame carries (as applied by the daemon's tick, so the same function
// of the same inputs: docs/frame-formats.md, Recordings). The frames carry
// only the skin and the inputs; this copy provides what they do not: the
// skeleton, the SPH particles and their pressure, the metaballs, muscles and
// bar-net nodes, the plain-skinning surface (for the displacement colouring)
// and each stage's step time on this host.
//
// It matches the daemon's state only while it sees every frame from the
// start of the run: a live stream that lost frames, or a viewer started
// mid-run, leaves the stateful layers (SPH, metaballs' jiggle) approximate.
// The drawn skin is always the stream's own.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "hal/output/pose_decode.hpp"
#include "sim_core/pipeline/pipeline.hpp"
#include "view_rig.hpp"

namespace sinew::view {

struct ShadowStep {
  uint64_t tick = 0;
  std::array<uint64_t, pipeline::kStageCount> stage_ns{};  // 0 for a stage that is off
  bool layer_error = false;
};

class ShadowPipeline {
 public:
  // Builds the pipeline with the layers `options` leaves on; false with
  // *error. options.tick_hz: the stream's tick rate (--tick-hz), or 0 to
  // take it from the frames (step_frame).
  bool init(const ViewRig& rig, const pipeline::PipelineOptions& options, std::string* error);
  // Back to the rig's rest state (a replay seeking backwards); the stream's
  // rate, once known, is kept.
  bool reset(std::string* error);
  // One tick with the frame's inputs (the rig's, then external ones), at the
  // stream's tick rate. sinewd converts the SPH gains to its loop's rate
  // (pipeline::sph_gains_for_rate), so the same inputs stepped at another
  // rate leave the particles and the bend elsewhere than the daemon's. Unless
  // init fixed the rate, the first frame is stepped at the rig's compiled
  // rate; the second gives the rate (tick and timestamp differences, to the
  // nearest hertz) and, when it differs, the pipeline restarts at it and
  // re-steps the first frame before this one.
  ShadowStep step_frame(const hal::output::DecodedPose& pose);
  // The rate the layers are stepped at; 0: the rig's compiled rate.
  uint32_t tick_hz() const { return options_.tick_hz; }

  uint64_t steps() const { return steps_; }
  const pipeline::Pipeline& state() const { return pipeline_; }
  bool stage_on(pipeline::Stage s) const { return pipeline::pipeline_stage_on(pipeline_, s); }
  // The surface plain skinning gave this tick (Q12.20 rig units, SoA).
  const std::vector<int32_t>& plain_skin(int axis) const { return plain_[axis]; }

 private:
  const ViewRig* rig_ = nullptr;
  pipeline::PipelineOptions options_;
  std::vector<uint64_t> arena_;
  pipeline::Pipeline pipeline_;
  std::vector<int32_t> plain_[3];
  uint64_t steps_ = 0;
  bool rate_known_ = false;
  bool have_first_ = false;
  uint64_t first_tick_ = 0, first_ns_ = 0;
  std::vector<int32_t> first_inputs_;

  ShadowStep step(uint64_t tick, std::span<const int32_t> inputs);
};

}  // namespace sinew::view
