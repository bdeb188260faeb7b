#include "sph_layer.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "hal/common/pose_frame.hpp"
#include "host_tools/layers/sph/sph_builder.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/sph/sph_step.hpp"

namespace sinew::firmware {

namespace {

class SphLayer final : public PoseLayer {
 public:
  const char* name() const override { return "sph"; }

  bool apply(engine::Engine& engine, std::span<const int32_t> inputs) override {
    if (inputs.size() <= force_input_) return false;
    sph::SphInputs in;
    in.transforms = engine.model;
    in.tresca = true;
    if (!sph::sph_flexion_force(model_, engine.model, inputs[force_input_], &in.force)) return false;
    // The first commanded pose may be far from the rest pose the particles
    // were initialised in: start them at rest in it, not with a jump.
    if (!started_ && !sph::sph_reset(&state_, engine.model).ok()) return false;
    started_ = true;
    if (!sph::sph_step(&state_, in).ok()) return false;
    // The particles' bend flexes the driven joint (docs/sph.md, call sequence).
    std::copy_n(inputs.begin(), flexed_.size(), flexed_.begin());
    // Saturated at +-180 deg rather than wrapped: past its limit the engine
    // clamps the joint (and flags it), a wrapped angle would swing it back.
    const int64_t bent = int64_t{flexed_[driven_input_]} + static_cast<int32_t>(state_.bend);
    flexed_[driven_input_] = static_cast<int32_t>(std::clamp<int64_t>(bent, INT32_MIN, INT32_MAX));
    if (!engine::engine_step(&engine, flexed_)) return false;
    sph::sph_apply_skin(state_, engine.vertices.position);
    return true;
  }

  void flag_inputs(std::span<uint8_t> status) const override {
    if (state_.joint_yielded && driven_input_ < status.size()) status[driven_input_] |= hal::kJointYielded;
  }

  layers::SphBuilt built_;
  sph::SphModel model_;
  std::vector<uint64_t> memory_;
  sph::SphState state_;
  std::vector<int32_t> flexed_;  // the rig's inputs with the bend added
  size_t driven_input_ = 0;
  size_t force_input_ = 0;
  bool started_ = false;
};

}  // namespace

std::unique_ptr<PoseLayer> make_arm_sph_layer(LoadedRig* rig, const SphLayerOptions& options, std::string* error) {
  auto layer = std::make_unique<SphLayer>();
  layers::SphBuildOptions build;
  build.particle_count = options.particles;
  build.tick_hz = options.tick_hz;
  // Substeps short enough for the explicit integration at any loop rate:
  // dt <= 5 ms (k_e dt^2 <= 0.075, as at 100 Hz with the default 2), e.g.
  // 2 at 100 Hz and above, 8 at 25 Hz; below 12.5 Hz the model's limit of 16
  // substeps makes the validator refuse the rate.
  build.substeps =
      std::max<uint32_t>(build.substeps, (200 + options.tick_hz - 1) / std::max<uint32_t>(1, options.tick_hz));
  if (!layers::build_sph(rigc::builtin_arm(), build, &layer->built_, error))
    return *error = "sph layer: " + *error, nullptr;
  layer->model_ = layer->built_.model();
  const sph::SphStatus valid = sph::sph_validate(layer->model_, rig->rig.joint_count(), rig->rig.vertex_count());
  if (!valid.ok()) return *error = std::string("sph layer: ") + valid.message, nullptr;

  // The rest pose's model transforms, from an engine of the loaded rig.
  std::vector<uint64_t> engine_arena(engine::engine_arena_bytes(rig->rig) / 8 + 1, 0);
  engine::Engine rest;
  if (!engine::engine_init(rig->rig, engine_arena.data(), engine_arena.size() * 8, &rest))
    return *error = "sph layer: engine arena", nullptr;
  layer->memory_.assign(sph::sph_state_bytes(layer->model_) / 8 + 1, 0);
  const sph::SphStatus s =
      sph::sph_init(layer->model_, rest.model, layer->memory_.data(), layer->memory_.size() * 8, &layer->state_);
  if (!s.ok()) return *error = std::string("sph layer: ") + s.message, nullptr;

  const rig::JointRecord& distal = rig->rig.joints[layer->model_.joint.distal_joint];
  layer->driven_input_ = distal.first_input;
  layer->flexed_.assign(rig->rig.input_count, 0);
  const std::string joint = rig->rig.names.empty() ? "joint" + std::to_string(layer->model_.joint.distal_joint)
                                                   : std::string(rig->rig.names[layer->model_.joint.distal_joint]);
  const auto limit = static_cast<int32_t>(std::lround(options.force_max_n * 65536.0));
  layer->force_input_ = rig->add_external({joint + ".force", -limit, limit, true});
  return layer;
}

}  // namespace sinew::firmware
