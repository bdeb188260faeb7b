#include "anatomy_layer.hpp"

#include <vector>

#include "host_tools/layers/anatomy/anatomy_build.hpp"
#include "host_tools/layers/anatomy/anatomy_spec.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/elastic_skin/skin_state.hpp"
#include "sim_core/elastic_skin/skin_step.hpp"
#include "sim_core/muscle/muscle_state.hpp"
#include "sim_core/muscle/muscle_step.hpp"

namespace sinew::firmware {

namespace {

class AnatomyLayer final : public PoseLayer {
 public:
  const char* name() const override { return "anatomy"; }
  bool apply(engine::Engine& engine, std::span<const int32_t>) override {
    if (!muscle::muscle_step(muscles_, engine.model, &muscle_state_).ok()) return false;
    if (!elastic_skin::skin_step(skin_, muscles_, muscle_state_, engine.model, &skin_state_).ok()) return false;
    for (int c = 0; c < 3; ++c)
      for (size_t v = 0; v < skin_.vertex_count && v < engine.vertices.position[c].size(); ++v)
        engine.vertices.position[c][v] = skin_state_.position[c][v];
    return true;
  }

  anatomy_build::AnatomyModel model_;
  muscle::MuscleModel muscles_;
  elastic_skin::SkinModel skin_;
  std::vector<uint64_t> muscle_memory_, skin_memory_;
  muscle::MuscleState muscle_state_;
  elastic_skin::SkinState skin_state_;
};

}  // namespace

std::unique_ptr<PoseLayer> make_arm_anatomy_layer(const rig::Rig& rig, int iterations, std::string* error) {
  auto layer = std::make_unique<AnatomyLayer>();
  anatomy_build::AnatomySpec spec = anatomy_build::arm_anatomy(rigc::builtin_arm());
  spec.skin.iterations = iterations;
  spec.skin.warm_start = true;
  if (!anatomy_build::build_anatomy(rig, spec, &layer->model_, error))
    return *error = "anatomy layer: " + *error, nullptr;
  layer->muscles_ = layer->model_.muscle_model();
  layer->skin_ = layer->model_.skin_model();
  if (layer->skin_.vertex_count != rig.vertex_count())
    return *error = "anatomy layer: built for a different rig than the one loaded", nullptr;
  layer->muscle_memory_.assign(muscle::muscle_state_bytes(layer->muscles_) / 8 + 1, 0);
  layer->skin_memory_.assign(elastic_skin::skin_state_bytes(layer->skin_) / 8 + 1, 0);
  if (!muscle::muscle_state_init(layer->muscles_, layer->muscle_memory_.data(), layer->muscle_memory_.size() * 8,
                                 &layer->muscle_state_)
           .ok() ||
      !elastic_skin::skin_state_init(layer->skin_, layer->skin_memory_.data(), layer->skin_memory_.size() * 8,
                                     &layer->skin_state_)
           .ok())
    return *error = "anatomy layer: state init failed", nullptr;
  return layer;
}

}  // namespace sinew::firmware
